# Install rules and the exported package: find_package(wearscar) then link
# wearscar::scan, wearscar::force, wearscar::fusion (with its parts
# fusion_estimate, fusion_compare, fusion_units, diagnose, fusion_products),
# wearscar::report or wearscar::samples.
include(CMakePackageConfigHelpers)

set(WEARSCAR_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/wearscar)

# PCL's include directories and libraries travel with this INTERFACE target,
# which the static libraries link privately; it has to be exported with them.
set_target_properties(wearscar_pcl PROPERTIES EXPORT_NAME pcl_deps)

# Three components, three Debian packages: wearscar (the command, its man
# pages and documentation), libwearscar-dev (headers, static libraries, the
# CMake package) and python3-wearscar (python/CMakeLists.txt).
install(TARGETS wearscar_support wearscar_scan wearscar_force
                wearscar_fusion_estimate wearscar_fusion_compare
                wearscar_fusion_units wearscar_diagnose
                wearscar_fusion_products wearscar_fusion
                wearscar_report wearscar_samples wearscar_pcl
        EXPORT wearscarTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS wearscar RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        COMPONENT wearscar)
foreach(module support scan force fusion/estimate fusion/compare fusion/units
               fusion/diagnose
               fusion/products fusion/pipeline apps/report samples)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/include/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
endforeach()
# Debian's place for a package's licence and changelog, in each package,
# and the documents for users. The changelog (Debian's format, native
# package) says the version and points at CHANGELOG.md; gzip -9n as
# Debian's tools compress it.
execute_process(COMMAND git log -1 --format=%aD
                WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                OUTPUT_VARIABLE commit_date
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT commit_date)
  string(TIMESTAMP commit_date "%a, %d %b %Y %H:%M:%S +0000" UTC)
endif()
find_program(WEARSCAR_GZIP gzip REQUIRED)
set(doc_packages wearscar libwearscar-dev python3-wearscar)
set(doc_components wearscar dev python3-wearscar)
foreach(package component IN ZIP_LISTS doc_packages doc_components)
  set(changelog ${PROJECT_BINARY_DIR}/debian/${package}/changelog)
  file(WRITE ${changelog}.in
"${package} (${PROJECT_VERSION}) unstable; urgency=medium

  * wearscar ${PROJECT_VERSION}; what changed is in
    /usr/share/doc/wearscar/CHANGELOG.md.

 -- @WEARSCAR_MAINTAINER@  ${commit_date}
")
  # (the maintainer is known further down; the file is made at build time)
  list(APPEND debian_changelogs ${changelog}.gz)
  install(FILES ${changelog}.gz
          DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${package}
          COMPONENT ${component})
  install(FILES ${PROJECT_SOURCE_DIR}/LICENSE
          DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${package} RENAME copyright
          COMPONENT ${component})
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/CHANGELOG.md
              ${PROJECT_SOURCE_DIR}/docs/method.md
              ${PROJECT_SOURCE_DIR}/docs/results.md
              ${PROJECT_SOURCE_DIR}/docs/formats.md
              ${PROJECT_SOURCE_DIR}/docs/watch.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT wearscar)

# Man pages for wearscar and each subcommand, from their own --help by
# help2man (Debian's help2man; without it, none, and CMake says so), each
# named for its command (NAME "wearscar-audit - ...": whatis finds it) and
# compressed. Not in instrumented builds, whose command is not the one
# installed.
find_program(WEARSCAR_HELP2MAN help2man)
if(WEARSCAR_HELP2MAN AND wearscar_uninstrumented)
  set(pages)
  set(subcommands "" simulate force scan fuse diagnose audit watch)
  set(summaries
      "friction coefficient of reciprocating tests from force and scan"
      "simulate reciprocating friction tests and scans with known truth"
      "analyse a friction test's force record alone (k from the spring)"
      "read a profilometer scan of the worn track and its centreline"
      "friction coefficient of one test from its force record and scan"
      "name the effect a wear-scar model misses in a friction test"
      "analyse a batch of specimens into one summary and report"
      "follow a friction test while it runs: mu per cycle, alerts")
  foreach(sub summary IN ZIP_LISTS subcommands summaries)
    if(sub STREQUAL "")
      set(name wearscar)
      set(help "--help")
    else()
      set(name wearscar-${sub})
      set(help "${sub} --help")
    endif()
    set(page ${PROJECT_BINARY_DIR}/man/${name}.1)
    add_custom_command(
      OUTPUT ${page}.gz
      COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/man
      COMMAND ${WEARSCAR_HELP2MAN} --no-info --no-discard-stderr
              "--name=${summary}" "--help-option=${help}"
              --version-option=--version --output=${page}
              $<TARGET_FILE:wearscar>
      COMMAND ${CMAKE_COMMAND} -DPAGE=${page} -DNAME=${name}
              -P ${PROJECT_SOURCE_DIR}/cmake/WearscarManPage.cmake
      COMMAND ${WEARSCAR_GZIP} -9nf ${page}
      DEPENDS wearscar ${PROJECT_SOURCE_DIR}/cmake/WearscarManPage.cmake
      VERBATIM)
    list(APPEND pages ${page}.gz)
  endforeach()
  add_custom_target(wearscar_man ALL DEPENDS ${pages})
  install(FILES ${pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1
          COMPONENT wearscar)
elseif(NOT WEARSCAR_HELP2MAN)
  message(STATUS "help2man not found: no man pages (apt-get install help2man)")
endif()

install(EXPORT wearscarTargets
        NAMESPACE wearscar::
        DESTINATION ${WEARSCAR_CMAKE_DIR} COMPONENT dev)
configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/cmake/wearscarConfig.cmake.in
  ${PROJECT_BINARY_DIR}/wearscarConfig.cmake
  INSTALL_DESTINATION ${WEARSCAR_CMAKE_DIR})
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/wearscarConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/wearscarConfig.cmake
              ${PROJECT_BINARY_DIR}/wearscarConfigVersion.cmake
        DESTINATION ${WEARSCAR_CMAKE_DIR} COMPONENT dev)

# Debian packages: cpack -G DEB in the build folder writes one per
# component, wearscar_<version>_amd64.deb, libwearscar-dev_... and
# python3-wearscar_..., their Depends computed by dpkg-shlibdeps plus what
# a program needs besides. The maintainer: WEARSCAR_MAINTAINER, by default
# the author of the commit built.
execute_process(COMMAND git log -1 "--format=%an <%ae>"
                WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                OUTPUT_VARIABLE commit_author
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT commit_author)
  set(commit_author "wearscar maintainers <wearscar@users.noreply.github.com>")
endif()
set(WEARSCAR_MAINTAINER "${commit_author}" CACHE STRING
    "The Debian packages' maintainer, 'Name <address>'")
foreach(changelog IN LISTS debian_changelogs)
  string(REGEX REPLACE "\\.gz$" "" text ${changelog})
  configure_file(${text}.in ${text} @ONLY)
  add_custom_command(OUTPUT ${changelog}
                     COMMAND ${WEARSCAR_GZIP} -9nkf ${text}
                     DEPENDS ${text} VERBATIM)
endforeach()
add_custom_target(wearscar_debian_changelogs ALL DEPENDS ${debian_changelogs})
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL wearscar dev python3-wearscar)
set(CPACK_PACKAGE_NAME wearscar)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "the wearscar authors")
set(CPACK_PACKAGE_CONTACT "${WEARSCAR_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${WEARSCAR_MAINTAINER}")
# (no CPACK_PACKAGE_DESCRIPTION_SUMMARY: CPack would prepend it to every
# package's description, whose first line is already its synopsis)
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # <package>_<version>_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_LICENSE BSD-3-Clause)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Stripped as Debian ships them, what is stripped kept apart in -dbgsym
# packages (.ddeb): the symbol table of every build, the debug information
# of one that has it (RelWithDebInfo, Debug). CPack strips when it splits
# (CPACK_STRIP_FILES would strip first, leaving nothing to keep);
# WearscarDebugSymbols.cmake makes the .ddeb files as Debian's tools do.
set(CPACK_STRIP_FILES OFF)
set(CPACK_DEBIAN_DEBUGINFO_PACKAGE ON)
set(CPACK_POST_BUILD_SCRIPTS ${PROJECT_SOURCE_DIR}/cmake/WearscarDebugSymbols.cmake)
set(CPACK_DEBIAN_WEARSCAR_PACKAGE_NAME wearscar)
set(CPACK_DEBIAN_WEARSCAR_PACKAGE_DEPENDS "gnuplot-nox")
# Descriptions: lines of at most 80 characters (Debian policy 3.4.1).
set(CPACK_DEBIAN_WEARSCAR_DESCRIPTION
    "sliding friction coefficient of reciprocating tests from force and scan
wearscar identifies the sliding friction coefficient of reciprocating
friction tests whose loops look non-Coulomb, from the tribometer's force
record and a profilometer scan of the worn track (the wear-scar
interaction). This package holds the command, its man pages and the
documentation.")
set(CPACK_DEBIAN_DEV_PACKAGE_NAME libwearscar-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
    "libeigen3-dev, libceres-dev, libopencv-dev, libpcl-dev, libfmt-dev, nlohmann-json3-dev, libzip-dev, libzstd-dev, zlib1g-dev, libssl-dev, libpugixml-dev, libpng-dev, libfftw3-dev, libxlsxwriter-dev")
set(CPACK_DEBIAN_DEV_DESCRIPTION
    "wearscar's C++ libraries (development files)
The headers, static libraries and CMake package of wearscar, which
identifies the sliding friction coefficient of reciprocating friction
tests from the force record and a scan of the worn track:
find_package(wearscar), then link wearscar::fusion and the others.")
set(CPACK_DEBIAN_PYTHON3-WEARSCAR_PACKAGE_NAME python3-wearscar)
set(CPACK_DEBIAN_PYTHON3-WEARSCAR_PACKAGE_SECTION python)
set(CPACK_DEBIAN_PYTHON3-WEARSCAR_PACKAGE_DEPENDS "${WEARSCAR_PYTHON_DEPENDS}")
set(CPACK_DEBIAN_PYTHON3-WEARSCAR_DESCRIPTION
    "wearscar's Python module
import wearscar: fuse, audit and simulate reciprocating friction tests
from Python, the results as dictionaries and NumPy arrays.")
include(CPack)
