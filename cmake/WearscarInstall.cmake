# Install rules and the exported package: find_package(wearscar) then link
# wearscar::scan, wearscar::force, wearscar::fusion or wearscar::samples.
include(CMakePackageConfigHelpers)

set(WEARSCAR_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/wearscar)

# PCL's include directories and libraries travel with this INTERFACE target,
# which the static libraries link privately; it has to be exported with them.
set_target_properties(wearscar_pcl PROPERTIES EXPORT_NAME pcl_deps)

install(TARGETS wearscar_scan wearscar_force wearscar_fusion wearscar_samples
                wearscar_pcl
        EXPORT wearscarTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS wearscar RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
foreach(module scan force fusion samples)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/include/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()

install(EXPORT wearscarTargets
        NAMESPACE wearscar::
        DESTINATION ${WEARSCAR_CMAKE_DIR})
configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/cmake/wearscarConfig.cmake.in
  ${PROJECT_BINARY_DIR}/wearscarConfig.cmake
  INSTALL_DESTINATION ${WEARSCAR_CMAKE_DIR})
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/wearscarConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/wearscarConfig.cmake
              ${PROJECT_BINARY_DIR}/wearscarConfigVersion.cmake
        DESTINATION ${WEARSCAR_CMAKE_DIR})
