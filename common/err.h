/* Error reporting shared by every cube5 module.
 * A fallible function returns 0 on success and -1 on failure, after writing one line
 * (no trailing newline) into a c5_err that names the file or key and the problem.
 * The command line prints it as "cube5: error: <msg>" and exits with C5_EXIT_INPUT.
 * Control characters in the message (from a key or a file name) become "?". */
#ifndef C5_ERR_H
#define C5_ERR_H

#define C5_EXIT_INPUT 2   /* bad input: file, dims, scene, option */
#define C5_EXIT_RUNTIME 1 /* anything else that failed (I/O while writing, out of memory) */

typedef struct {
    char msg[1024];
} c5_err;

/* printf-style; always returns -1 so that "return c5_fail(err, ...);" reads naturally. */
int c5_fail(c5_err *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
