/* A minimal unit-test harness: TEST() registers a case at start-up, CHECK*() fail the case
 * with file, line and the values involved. tests/run.sh aggregates every suite into the
 * closing line "N passed, N failed". */
#ifndef C5_HARNESS_H
#define C5_HARNESS_H

#include <math.h>
#include <stdio.h>

typedef void (*c5t_fn)(void);
void c5t_register(const char *name, c5t_fn fn);
void c5t_failf(const char *file, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
int c5t_failed_now(void);
/* JSON written with ' for " (readable in C strings): the text with every ' turned into ".
 * Returns a static buffer, valid until the next call. */
const char *c5t_json(const char *s);
/* A fresh empty directory for this test case, removed after the run. */
const char *c5t_tmpdir(void);
/* Path of a file inside c5t_tmpdir(); valid until the next call with the same slot. */
const char *c5t_path(int slot, const char *name);
/* Writes an optional text header followed by n raw bytes to path; 0 on success. */
int c5t_write_file(const char *path, const char *header, const void *data, size_t n);

#define TEST(name)                                                                       \
    static void name(void);                                                              \
    __attribute__((constructor)) static void c5t_reg_##name(void) { c5t_register(#name, name); } \
    static void name(void)

#define CHECK(cond)                                                        \
    do {                                                                   \
        if (!(cond)) {                                                     \
            c5t_failf(__FILE__, __LINE__, "CHECK(%s)", #cond);             \
            return;                                                        \
        }                                                                  \
    } while (0)

#define CHECK_MSG(cond, ...)                                               \
    do {                                                                   \
        if (!(cond)) {                                                     \
            c5t_failf(__FILE__, __LINE__, __VA_ARGS__);                    \
            return;                                                        \
        }                                                                  \
    } while (0)

#define CHECK_INT(a, b)                                                                  \
    do {                                                                                 \
        long long c5t_a = (long long)(a), c5t_b = (long long)(b);                        \
        if (c5t_a != c5t_b) {                                                            \
            c5t_failf(__FILE__, __LINE__, "%s == %s: %lld != %lld", #a, #b, c5t_a, c5t_b); \
            return;                                                                      \
        }                                                                                \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                  \
    do {                                                                                       \
        double c5t_a = (double)(a), c5t_b = (double)(b);                                       \
        if (!(fabs(c5t_a - c5t_b) <= (tol))) {                                                 \
            c5t_failf(__FILE__, __LINE__, "%s ~ %s: %.17g vs %.17g (tol %g)", #a, #b, c5t_a, c5t_b, \
                      (double)(tol));                                                          \
            return;                                                                            \
        }                                                                                      \
    } while (0)

/* Checks that an error message contains a substring. */
#define CHECK_HAS(msg, needle)                                                              \
    do {                                                                                    \
        if (!strstr((msg), (needle))) {                                                     \
            c5t_failf(__FILE__, __LINE__, "expected \"%s\" in message \"%s\"", (needle), (msg)); \
            return;                                                                         \
        }                                                                                   \
    } while (0)

#endif
