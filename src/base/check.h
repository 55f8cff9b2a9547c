// Checks for programming errors (never for bad user input, which gets an InputError):
// RAYCAST_CHECK is always on. RAYCAST_DCHECK states an invariant that hot code relies on (a stack
// bound, an index range): it is checked in debug builds and in sanitizer builds, where the
// build defines RAYCAST_ENABLE_DCHECKS (the RAYCAST_DCHECKS option of CMakeLists.txt), and costs
// nothing in Release, where the condition is compiled but never evaluated. A failed check aborts.
#pragma once

#include <cstdio>
#include <cstdlib>

#define RAYCAST_CHECK(condition)                                                              \
    do {                                                                                      \
        if (!(condition)) {                                                                   \
            std::fprintf(stderr, "%s:%d: internal error: check failed: %s\n", __FILE__,       \
                         __LINE__, #condition);                                               \
            std::abort();                                                                     \
        }                                                                                     \
    } while (false)

#if defined(RAYCAST_ENABLE_DCHECKS) || !defined(NDEBUG)
#define RAYCAST_DCHECKS_ENABLED 1
#define RAYCAST_DCHECK(condition) RAYCAST_CHECK(condition)
#else
#define RAYCAST_DCHECKS_ENABLED 0
// Still compiled, so that a check cannot rot and what it names counts as used.
#define RAYCAST_DCHECK(condition)           \
    do {                                    \
        if (false) {                        \
            static_cast<void>(condition);   \
        }                                   \
    } while (false)
#endif
