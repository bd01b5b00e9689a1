/* Minimal test assertions: each failure prints file:line and the message;
 * a test's main returns check_finish(). */
#ifndef SB_CHECK_H
#define SB_CHECK_H

#include <math.h>
#include <stdio.h>

static int check_failures, check_count;

#define CHECK(cond, ...)                                            \
    do {                                                            \
        check_count++;                                              \
        if (!(cond)) {                                              \
            check_failures++;                                       \
            fprintf(stderr, "%s:%d: FAILED: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                           \
            fputc('\n', stderr);                                    \
        }                                                           \
    } while (0)

/* |a - b| <= tol, with the reason for tol stated at the call. */
#define CHECK_NEAR(a, b, tol, ...) \
    CHECK(fabs((double)(a) - (double)(b)) <= (tol), "%.9g vs %.9g (tol %g): " __VA_ARGS__, \
          (double)(a), (double)(b), (double)(tol))

static inline int check_finish(void)
{
    printf("%d passed, %d failed\n", check_count - check_failures, check_failures);
    return check_failures ? 1 : 0;
}

#endif
