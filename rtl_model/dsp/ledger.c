/* The DSP's ledger of a camera path (ledger.h). */
#include <math.h>

#include "ledger.h"

int64_t c5_ledger_allowance(const c5_stale_plan *p)
{
    int64_t mw = p && p->valid ? p->maxwork_loads : 0;
    int64_t a = (int64_t)ceil(C5_LEDGER_ALLOWANCE_PCT / 100.0 * (double)mw);
    return a > 1 ? a : 1;
}

/* Whether the frame risks an allowance beyond the bank: not when the previous frame's replay
 * shows that the schedule followed there, followed to its end, would have saved less than an
 * allowance on that frame's tree (lag_loads, exact: the last camera step says the path moves
 * too fast for a one-frame-old schedule). Without that replay (the path's first followed
 * frame, a frame after Max Work), not when the set-up's queues overlap the previous frame's
 * little (a cut, a fast move). */
static int risk(const c5_stale_plan *p, double start_overlap)
{
    if (!p || !p->valid || p->lag_loads < 0)
        return start_overlap < 0 || start_overlap >= C5_LEDGER_START_OVERLAP;
    return (int64_t)p->maxwork_loads - p->lag_loads >= c5_ledger_allowance(p);
}

int64_t c5_ledger_budget(const c5_stale_plan *p, uint64_t frame_key, double start_overlap, int *identical)
{
    *identical = p && p->valid && p->frame_key == frame_key;
    if (*identical)
        return p->sched_loads <= p->maxwork_loads ? INT64_MAX / 2 : 0;
    return (p ? p->bank : 0) + (risk(p, start_overlap) ? c5_ledger_allowance(p) : 0);
}

/* FNV-1a over the registers' bytes, field by field (no padding). */
uint64_t c5_frame_key(const c5_camera *c, int w, int h)
{
    double v[10] = {c->eye.x, c->eye.y, c->eye.z, c->target.x, c->target.y, c->target.z, c->up.x, c->up.y, c->up.z,
                    c->fov_deg};
    int d[2] = {w, h};
    uint64_t k = 0xcbf29ce484222325ULL;
    const unsigned char *b = (const unsigned char *)v;
    for (size_t i = 0; i < sizeof v; i++)
        k = (k ^ b[i]) * 0x100000001b3ULL;
    b = (const unsigned char *)d;
    for (size_t i = 0; i < sizeof d; i++)
        k = (k ^ b[i]) * 0x100000001b3ULL;
    return k;
}
