# Non-exported INTERFACE target carrying warnings and sanitizer flags. Every
# wearscar target links it PRIVATE, so nothing leaks to consumers.
add_library(wearscar_warnings INTERFACE)
target_compile_options(wearscar_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow
  $<$<BOOL:${WEARSCAR_WERROR}>:-Werror>)

if(WEARSCAR_SANITIZE)
  string(REPLACE " " "" _sanitizers "${WEARSCAR_SANITIZE}")
  # -fsanitize=undefined leaves out float-cast-overflow (a double beyond an
  # int's range cast to int): ask for it by name, GCC and clang alike.
  if(_sanitizers MATCHES "undefined" AND NOT _sanitizers MATCHES "float-cast-overflow")
    string(APPEND _sanitizers ",float-cast-overflow")
  endif()
  target_compile_options(wearscar_warnings INTERFACE
    -fsanitize=${_sanitizers} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(wearscar_warnings INTERFACE -fsanitize=${_sanitizers})
  # Preconditions are checked in sanitizer builds (wearscar/support/check.h).
  target_compile_definitions(wearscar_warnings INTERFACE WEARSCAR_CHECKS=1)
  # GCC's -Wmaybe-uninitialized misfires on instrumented code (std::regex,
  # std::function in libstdc++ 12); with -Werror it would stop the build.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(wearscar_warnings INTERFACE -Wno-maybe-uninitialized)
  endif()
  # Eigen switches to its own aligned allocator under AddressSanitizer, but
  # Debian's PCL, OpenCV and Ceres were built with glibc's (already 16-byte
  # aligned) malloc. Eigen objects crossing that boundary would then be freed
  # by the wrong allocator; keep ours the same as theirs.
  target_compile_definitions(wearscar_warnings INTERFACE EIGEN_MALLOC_ALREADY_ALIGNED=1)
  message(STATUS "wearscar: sanitizers ${_sanitizers}")
endif()

if(WEARSCAR_FUZZ)
  # Instrument the libraries for coverage; the targets link the fuzzer.
  target_compile_options(wearscar_warnings INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined,float-cast-overflow
    -fno-omit-frame-pointer)
  target_link_options(wearscar_warnings INTERFACE
    -fsanitize=address,undefined,float-cast-overflow)
  target_compile_definitions(wearscar_warnings INTERFACE WEARSCAR_CHECKS=1)
endif()
