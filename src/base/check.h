// Checks for programming errors (never for bad user input, which gets an InputError):
// RAYCAST_CHECK is always on, RAYCAST_DCHECK only in debug builds. A failed check aborts.
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

#ifdef NDEBUG
#define RAYCAST_DCHECK(condition) \
    do {                          \
    } while (false)
#else
#define RAYCAST_DCHECK(condition) RAYCAST_CHECK(condition)
#endif
