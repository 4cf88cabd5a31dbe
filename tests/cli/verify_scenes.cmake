# Every shipped scene with "interfaces" passes its own `shellfrac verify coupling` at its shipped
# resolution: seam gap, normal angle and stress ratio of each interface, and the render
# mesh's peak edge stretch, against the scene's limits (defaults in docs/scene-format.md). One ctest test
# per scene, so that they can run apart (the drapes take about a minute each on 2 cores); exit 0 is the
# assertion (4: a check failed).
file(GLOB _shipped_scenes "${PROJECT_SOURCE_DIR}/scenes/*.json")
foreach(_scene ${_shipped_scenes})
  file(READ "${_scene}" _text)
  string(FIND "${_text}" "\"interfaces\"" _has_interfaces)
  if(_has_interfaces EQUAL -1)
    continue()
  endif()
  get_filename_component(_name "${_scene}" NAME_WE)
  add_test(NAME verify_coupling.${_name}
           COMMAND shellfrac verify coupling "${_scene}" --out "${CMAKE_CURRENT_BINARY_DIR}/verify_${_name}" --threads 2)
  set_tests_properties(verify_coupling.${_name} PROPERTIES TIMEOUT 900 LABELS "cli;verify_scenes" COST 30)  # whole runs, up to ~40 s
endforeach()
