#include "err.h"

#include <stdarg.h>
#include <stdio.h>

int c5_fail(c5_err *err, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        /* One line whatever the user's text held: a JSON key or a file name may carry a
         * newline or an escape sequence into the message (found by fuzz/fuzz_scene.c). */
        for (char *p = err->msg; *p; p++)
            if ((unsigned char)*p < 0x20 || *p == 0x7f)
                *p = '?';
    }
    return -1;
}
