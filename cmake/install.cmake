# The installable package: every layer as shellfrac::<layer> (the same names as ALIAS targets in the build
# tree), the headers under <prefix>/include/shellfrac/<layer>/, and a package config for
# find_package(shellfrac). examples/consumer/ is a project that uses it (tested by tests/install/).
include(CMakePackageConfigHelpers)
include(GNUInstallDirs)

set(SHELLFRAC_LAYERS core nurbs crack2d mpm brittle rigid shatter coupling shell render_mesh scene sim output tools)
foreach(layer ${SHELLFRAC_LAYERS})
  add_library(shellfrac::${layer} ALIAS shellfrac_${layer})
  set_target_properties(shellfrac_${layer} PROPERTIES EXPORT_NAME ${layer})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${layer}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/shellfrac/${layer}
          FILES_MATCHING PATTERN "*.hpp")
endforeach()
list(TRANSFORM SHELLFRAC_LAYERS PREPEND shellfrac_ OUTPUT_VARIABLE _targets)
install(TARGETS ${_targets} shellfrac_options EXPORT shellfracTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS shellfrac RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${PROJECT_BINARY_DIR}/generated/core/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/shellfrac/core)
install(EXPORT shellfracTargets NAMESPACE shellfrac:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/shellfrac)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/shellfracConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/shellfracConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/shellfrac)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/shellfracConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/shellfracConfig.cmake ${PROJECT_BINARY_DIR}/shellfracConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/shellfrac)
