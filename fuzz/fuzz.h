/* What every harness in fuzz/ shares. A harness is one LLVMFuzzerTestOneInput: built with
 * clang -fsanitize=fuzzer,address,undefined by fuzz/run.sh (`make fuzz`), and with the normal
 * toolchain against fuzz/replay_main.c, which `make test` (and `make asan`) runs over the
 * committed corpus (fuzz/corpus/NAME/) as regression. A finding is a crash, a sanitizer report,
 * a leak, or an abort() from a harness's own check of what the code promised (c5_fuzz_expect). */
#ifndef C5_FUZZ_H
#define C5_FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A promise the code under test broke: say which and abort (a finding for libFuzzer, a
 * failed replay for make test). */
#define c5_fuzz_expect(cond, what)                                                     \
    do {                                                                               \
        if (!(cond)) {                                                                 \
            fprintf(stderr, "fuzz: %s:%d: broken promise: %s (%s)\n", __FILE__, __LINE__, \
                    what, #cond);                                                      \
            abort();                                                                   \
        }                                                                              \
    } while (0)

/* An error message the command line may print: non-empty, one line, NUL-terminated. */
static inline int c5_fuzz_one_line(const char *msg, size_t cap)
{
    size_t n = strnlen(msg, cap);
    return n > 0 && n < cap && !memchr(msg, '\n', n);
}

#endif
