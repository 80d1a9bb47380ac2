#include "progress.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "board.h"
#include "clock.h"

int c5_progress_requested;

/* On a terminal, nothing before this many seconds: a quick run prints no progress at all. */
#define C5_PROGRESS_QUIET_S 1.0

void c5_progress_begin(c5_progress *p, const char *cmd, int total)
{
    /* --progress: one line per step, on a terminal too; else a line redrawn in place on a
     * terminal, nothing elsewhere */
    p->mode = c5_progress_requested ? 2 : isatty(STDERR_FILENO) ? 1 : 0;
    p->cmd = cmd;
    p->total = total;
    p->t0 = c5_now_s();
    p->drawn = 0;
    p->last_note = 0;
    p->hinted = 0;
}

static void vline(c5_progress *p, int done, double t, const char *fmt, va_list ap)
{
    fprintf(stderr, "%scube5 %s: [%d/%d] ", p->mode == 1 ? "\r\033[K" : "", p->cmd, done, p->total);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (%.1f s)%s", t, p->mode == 1 ? "" : "\n");
    fflush(stderr);
    p->drawn = p->mode == 1;
}

/* Neither a terminal nor --progress: a run past this many seconds says once how to see its
 * progress, so a long command in a script or a pipe does not look hung. */
#define C5_PROGRESS_HINT_S 10.0

static void hint(c5_progress *p, double t)
{
    const char *e = getenv("C5_PROGRESS_HINT_S"); /* another threshold (tests) */
    if (p->mode || p->hinted || t < (e ? atof(e) : C5_PROGRESS_HINT_S))
        return;
    p->hinted = 1;
    fprintf(stderr, "cube5 %s: still running after %.0f s (--progress prints a line per step)\n", p->cmd, t);
}

void c5_progress_note(c5_progress *p, int done, const char *fmt, ...)
{
    double t = c5_now_s() - p->t0;
    hint(p, t);
    if (!p->mode || t - p->last_note < C5_PROGRESS_QUIET_S)
        return;
    p->last_note = t;
    va_list ap;
    va_start(ap, fmt);
    vline(p, done + 1, t, fmt, ap); /* the count names the step under way */
    va_end(ap);
}

void c5_progress_board(void *ctx, const struct c5_board_progress *bp)
{
    c5_progress_frame *f = ctx;
    c5_progress_note(f->p, f->done, "frame %d: %llu cell fetches, %llu rays queued", f->frame,
                     (unsigned long long)bp->fetches, (unsigned long long)bp->rays_queued);
}

void c5_progress_cref(void *ctx, int tiles_done, int tiles)
{
    c5_progress_frame *f = ctx;
    c5_progress_note(f->p, f->done, "frame %d: %d%% of the image", f->frame,
                     tiles > 0 ? (int)(100.0 * tiles_done / tiles) : 0);
}

void c5_progress_step(c5_progress *p, int done, const char *fmt, ...)
{
    double t = c5_now_s() - p->t0;
    hint(p, t);
    if (!p->mode || (p->mode == 1 && !c5_progress_requested && t < C5_PROGRESS_QUIET_S))
        return;
    va_list ap;
    va_start(ap, fmt);
    vline(p, done, t, fmt, ap);
    va_end(ap);
    p->last_note = t;
}

void c5_progress_end(c5_progress *p)
{
    if (p->drawn)
        fputs("\r\033[K", stderr);
    p->drawn = 0;
}
