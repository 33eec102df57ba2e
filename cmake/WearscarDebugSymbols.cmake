# CPack's post-build step (CPACK_POST_BUILD_SCRIPTS): the -dbgsym packages
# (.ddeb) that CPack splits off the stripped binaries, made as Debian's own
# tools make them. CMake 3.25 writes their md5sums with absolute paths of
# its staging folder and gives them no documentation folder; here each is
# unpacked, its md5sums written again relative to its root, its
# /usr/share/doc/<package>-dbgsym made a link to the package's own
# (copyright and changelog: the -dbgsym package depends on that very
# version), and packed again. A build without debug information (Release)
# still keeps its symbol table apart (function names for backtraces and
# profilers); lintian says debug-file-with-no-debug-symbols of it, which
# tests/package_deb.sh accepts for such a build only (a -dbgsym package
# may hold no lintian override).
find_program(dpkg_deb dpkg-deb REQUIRED)
set(folders)
foreach(package IN LISTS CPACK_PACKAGE_FILES)
  get_filename_component(folder "${package}" DIRECTORY)
  list(APPEND folders "${folder}")
endforeach()
list(REMOVE_DUPLICATES folders)
foreach(folder IN LISTS folders)
  file(GLOB ddebs "${folder}/*.ddeb")
  foreach(ddeb IN LISTS ddebs)
    get_filename_component(file_name "${ddeb}" NAME)
    string(REGEX REPLACE "-dbgsym_.*$" "" package "${file_name}")
    set(tree "${CPACK_TOPLEVEL_DIRECTORY}/dbgsym/${package}")
    file(REMOVE_RECURSE "${tree}")
    file(MAKE_DIRECTORY "${tree}")
    execute_process(COMMAND ${dpkg_deb} -R "${ddeb}" "${tree}"
                    COMMAND_ERROR_IS_FATAL ANY)
    file(GLOB_RECURSE debug_files RELATIVE "${tree}" "${tree}/usr/*")
    list(SORT debug_files)
    set(sums "")
    foreach(f IN LISTS debug_files)
      file(MD5 "${tree}/${f}" sum)
      string(APPEND sums "${sum}  ${f}\n")
    endforeach()
    file(WRITE "${tree}/DEBIAN/md5sums" "${sums}")
    file(MAKE_DIRECTORY "${tree}/usr/share/doc")
    file(CREATE_LINK "${package}" "${tree}/usr/share/doc/${package}-dbgsym"
         SYMBOLIC)
    execute_process(COMMAND ${dpkg_deb} --root-owner-group -Zxz --build
                            "${tree}" "${ddeb}"
                    OUTPUT_QUIET COMMAND_ERROR_IS_FATAL ANY)
  endforeach()
endforeach()
