/* Bit-for-bit comparison of two board renders (board_equal.h). */
#include "board_equal.h"

#include <string.h>

#include "harness.h"

int c5t_board_stats_equal(const char *what, const c5_board_stats *a, const c5_board_stats *b)
{
    /* Field by field, not memcmp: padding bytes are not part of the result. */
#define SAME(f)                                                                                          \
    if (a->f != b->f) {                                                                                  \
        c5t_failf(__FILE__, __LINE__, "%s: %s %.17g != %.17g", what, #f, (double)a->f, (double)b->f);    \
        return -1;                                                                                       \
    }
    for (int i = 0; i < C5_RAY_TYPES; i++)
        SAME(rays[i]);
    for (int i = 0; i < C5_END_KINDS; i++)
        SAME(ends[i]);
    SAME(samples) SAME(samples_leaped) SAME(cycles) SAME(cycles_process) SAME(cycles_fetch) SAME(board_s)
    SAME(fetches) SAME(fetch_bytes) SAME(bus_packets) SAME(spills) SAME(queue_pops) SAME(queue_max)
    SAME(cache_hits) SAME(cache_misses) SAME(saturations) SAME(sched_loads) SAME(sched_skipped)
    SAME(sched_fallback) SAME(tree_nodes) SAME(tree_slots) SAME(tree_overflow) SAME(tree_tags) SAME(tree_reads)
    SAME(tree_writes) SAME(stages.gradients) SAME(stages.shadow) SAME(stages.reflect) SAME(stages.refract)
    SAME(stages.scheduling) SAME(cells)
#undef SAME
    return 0;
}

int c5t_same_image(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * (size_t)a->h);
}
