# OpenVDB: its own CMake package if the installation has one; otherwise its find module, which
# distributions (Debian among them) install under <libdir>/cmake/OpenVDB instead of CMake's module path.
# FindOpenVDB needs libboost-iostreams-dev, and TBB must be found first or the TBB targets clash.
find_package(OpenVDB CONFIG QUIET)
if(NOT OpenVDB_FOUND)
  find_path(SHELLFRAC_OPENVDB_MODULE_DIR FindOpenVDB.cmake
            PATHS ${CMAKE_PREFIX_PATH} ${CMAKE_INSTALL_PREFIX} /usr/local /usr
            PATH_SUFFIXES lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB lib/cmake/OpenVDB lib64/cmake/OpenVDB
                          share/OpenVDB/cmake
            NO_DEFAULT_PATH
            DOC "folder holding OpenVDB's FindOpenVDB.cmake")
  if(NOT SHELLFRAC_OPENVDB_MODULE_DIR)
    message(FATAL_ERROR "OpenVDB not found: install libopenvdb-dev (scripts/setup.sh does), or point "
                        "SHELLFRAC_OPENVDB_MODULE_DIR at the folder holding FindOpenVDB.cmake")
  endif()
  list(APPEND CMAKE_MODULE_PATH ${SHELLFRAC_OPENVDB_MODULE_DIR})
  find_package(OpenVDB REQUIRED)
endif()
