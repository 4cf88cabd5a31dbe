# Compiles the Blender scripts of `shellfrac preview` (apps/shellfrac/blender/preview.py and the shellfrac_mesh.py it
# imports) into the shellfrac binary, so the command finds them wherever the binary runs from (build/bin,
# an install prefix, a copy). Sets SHELLFRAC_PREVIEW_SCRIPT_CPP to the generated source.
foreach(_name PREVIEW MESH)
  if(_name STREQUAL PREVIEW)
    set(_py ${PROJECT_SOURCE_DIR}/apps/shellfrac/blender/preview.py)
  else()
    set(_py ${PROJECT_SOURCE_DIR}/apps/shellfrac/blender/shellfrac_mesh.py)
  endif()
  file(READ ${_py} SHELLFRAC_${_name}_PY)
  string(FIND "${SHELLFRAC_${_name}_PY}" ")shellfrac_py\"" _delimiter)
  if(NOT _delimiter EQUAL -1)
    message(FATAL_ERROR "${_py} contains the raw-string delimiter )shellfrac_py\" used to embed it")
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_py})
endforeach()
set(SHELLFRAC_PREVIEW_SCRIPT_CPP ${PROJECT_BINARY_DIR}/generated/apps/shellfrac/preview_script.cpp)
configure_file(${CMAKE_CURRENT_LIST_DIR}/preview_script.cpp.in ${SHELLFRAC_PREVIEW_SCRIPT_CPP} @ONLY)
