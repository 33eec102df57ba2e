# Install rules and the exported package: find_package(wearscar) then link
# wearscar::scan, wearscar::force, wearscar::fusion, wearscar::report or
# wearscar::samples.
include(CMakePackageConfigHelpers)

set(WEARSCAR_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/wearscar)

# PCL's include directories and libraries travel with this INTERFACE target,
# which the static libraries link privately; it has to be exported with them.
set_target_properties(wearscar_pcl PROPERTIES EXPORT_NAME pcl_deps)

install(TARGETS wearscar_support wearscar_scan wearscar_force wearscar_fusion wearscar_report wearscar_samples
                wearscar_pcl
        EXPORT wearscarTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS wearscar RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
foreach(module support scan force fusion apps/report samples)
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

# A Debian package: cpack -G DEB in the build folder writes
# wearscar_<version>_amd64.deb with the command, the Python module, the
# headers, the static libraries and the CMake package under /usr.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME wearscar)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "the wearscar authors")
set(CPACK_PACKAGE_CONTACT "the wearscar authors <wearscar@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "sliding friction coefficient of reciprocating tests from force and scan")
set(CPACK_PACKAGE_DESCRIPTION
    "wearscar identifies the sliding friction coefficient of reciprocating \
friction tests whose loops look non-Coulomb, from the tribometer's force \
record and a profilometer scan of the worn track (the wear-scar interaction). \
It installs the wearscar command, the Python module, the C++ headers, static \
libraries and CMake package.")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # wearscar_0.1.0_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_LICENSE BSD-3-Clause)
# Shared libraries the command and the module load, found by dpkg-shlibdeps;
# what a program needs besides.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "gnuplot-nox, python3, python3-numpy")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libceres-dev, libopencv-dev, libpcl-dev, nlohmann-json3-dev, libfmt-dev")
include(CPack)
