/* Whole or nothing: every file a cube5 tool writes goes to a temporary file beside its target;
 * every write, the flush, the sync and the close are checked, and only then is it renamed
 * into place. On any failure the temporary is removed, the target is as it was, and the
 * message names the target and the system's reason ("PATH: cannot write: No space left on
 * device"). A target that is a symbolic link is written through the link (the link stays).
 * README, "Conventions". */
#ifndef C5_ATOMIC_FILE_H
#define C5_ATOMIC_FILE_H

#include <stddef.h>
#include <stdio.h>

#include "err.h"

typedef struct {
    FILE *f;
    char path[4096];   /* the target (through a link: the file it names) */
    char shown[4096];  /* the target as the user gave it, for messages */
    char tmp[4200];
    int err_no;        /* the first failure's errno (of the open too); 0: none so far */
    int mode;          /* the replaced file's permissions; -1: a new file */
} c5_afile;

/* Creates the temporary beside `path`. 0, or -1 naming path and the reason. */
int c5_afile_open(c5_afile *a, const char *path, c5_err *err);
/* Writes; a failure is kept for c5_afile_commit (later writes are skipped). */
void c5_afile_write(c5_afile *a, const void *buf, size_t n);
void c5_afile_printf(c5_afile *a, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Flushes, syncs, closes and renames into place: 0, or -1 with the first failure (the
 * temporary removed). */
int c5_afile_commit(c5_afile *a, c5_err *err);
/* Drops the temporary (the target untouched); safe after a failed open or commit. */
void c5_afile_abort(c5_afile *a);
/* The temporary for `path` (".NAME.tmp-PID-N" beside it, then ext, or nothing): for a writer
 * that is not this module's (gnuplot), which renames it into place itself. */
void c5_afile_tmp_path(const char *path, const char *ext, char *out, size_t len);
/* The file an output path writes: the path, or the file its symbolic links name (followed
 * even when the last does not exist yet, as the shell's > does). 0, or -1 (errno: a loop). */
int c5_output_target(const char *path, char *out, size_t len);
/* Whether a file can be written at `path` (through its links): its folder exists, is a folder
 * and is writable, and the path is not a folder. Every tool checks each output with it before
 * any work, so a place that cannot hold the file is bad input (exit 2) found in a moment, not
 * a failure after the render. 0, or -1 naming path, the folder and the reason. */
int c5_output_check(const char *path, c5_err *err);
/* A folder of outputs (vectors --out, sweep --out): created with its missing parents (as
 * mkdir -p), refused when the path is something else. 0, or -1 naming dir. */
int c5_output_dir(const char *dir, c5_err *err);
/* The whole of buf[0..n) into path, as above. */
int c5_afile_put(const char *path, const void *buf, size_t n, c5_err *err);

#endif
