/* Progress of a long run, on stderr only (stdout keeps the summary or the --json object).
 * Shown when stderr is a terminal (one line redrawn in place, from the first second on, so
 * that short runs stay quiet) or with --progress (one line per step, at once: for logs and
 * for tests, which have no terminal). Lines read "cube5 CMD: [I/N] WHAT (T s)". */
#ifndef C5_CLI_PROGRESS_H
#define C5_CLI_PROGRESS_H

/* Set when the command line holds --progress (c5_progress_opts, opt_table.h). */
extern int c5_progress_requested;

typedef struct {
    int mode;        /* 0 off, 1 terminal (redrawn), 2 one line per step */
    const char *cmd; /* "render", ... */
    int total;
    double t0;
    int drawn; /* a terminal line is on screen */
    double last_note; /* when c5_progress_note last printed (seconds since t0) */
    int hinted;       /* the "--progress prints a line per step" hint was given */
} c5_progress;

void c5_progress_begin(c5_progress *p, const char *cmd, int total);
/* Step `done` of the total (1-based) has finished; WHAT is printf-style. */
void c5_progress_step(c5_progress *p, int done, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* Within step `done` + 1 (a long frame): WHAT, at most once a second (the first a second
 * after the step began), in the same form, counted as step done + 1; does not advance the
 * count. */
void c5_progress_note(c5_progress *p, int done, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* The board model's in-frame hook (c5_board_opts.progress) for a c5_progress: notes "frame F:
 * N cell fetches, M rays queued". ctx: a c5_progress_frame. */
typedef struct {
    c5_progress *p;
    int done, frame;
} c5_progress_frame;
struct c5_board_progress;
void c5_progress_board(void *ctx, const struct c5_board_progress *bp);
/* cref's in-frame hook (c5_cref_opts.progress): notes "frame F: P% of the image". ctx: a
 * c5_progress_frame. */
void c5_progress_cref(void *ctx, int tiles_done, int tiles);
/* Clears a terminal line, so that what follows on stderr starts on a clean line. */
void c5_progress_end(c5_progress *p);

#endif
