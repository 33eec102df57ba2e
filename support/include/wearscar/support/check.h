#pragma once

// Preconditions of the public entry points: WEARSCAR_CHECK(condition,
// "what must hold") aborts with the file, line, condition and message in
// debug and sanitizer builds (WEARSCAR_CHECKS defined), and costs nothing
// in release builds, where bad input is caught earlier and reported as an
// error. A failed check is a bug in the calling code, never bad input.

#include <cstdio>
#include <cstdlib>

#if defined(WEARSCAR_CHECKS) || !defined(NDEBUG)
#define WEARSCAR_CHECK(condition, message)                  \
  do {                                                      \
    if (!(condition)) {                                     \
      std::fprintf(stderr,                                  \
                   "%s:%d: precondition failed: %s (%s)\n", \
                   __FILE__,                                \
                   __LINE__,                                \
                   #condition,                              \
                   message);                                \
      std::abort();                                         \
    }                                                       \
  } while (false)
#else
#define WEARSCAR_CHECK(condition, message) \
  do {                                     \
    (void)sizeof(condition);               \
  } while (false)
#endif
