/* The frame's statistics (c5_board_stats, board.h) from the processor, the ray queues and
 * the Cell Trees, at the end of c5_board_render. */
#include "board_internal.h"

#include <string.h>

void c5_bd_collect_stats(c5_bd *b)
{
    c5_board_stats *stats = b->st;
    const c5_proc_stats *ps = &b->proc.st;
    memcpy(stats->rays, ps->rays, sizeof stats->rays);
    memcpy(stats->ends, ps->ends, sizeof stats->ends);
    stats->samples = ps->samples;
    stats->samples_leaped = ps->leaped;
    stats->cache_hits = ps->cache_hits;
    stats->cache_misses = ps->cache_misses;
    stats->saturations = ps->saturations;
    stats->queue_max = b->cycle_level ? b->edram.stats.max_count : b->heap.stats.max_count;
    stats->tree_nodes = b->tree->nodes;
    stats->tree_slots = b->tree->used;
    stats->tree_overflow = b->tree->overflow;
    stats->tree_demand_nodes = b->demand.oom ? 0 : b->demand.n;
    stats->tree_demand_slots = b->demand.oom ? 0 : c5_demand_slots(&b->demand, C5_TREE_CHILDREN);
    stats->tree_demand_slots6 = b->demand.oom ? 0 : c5_demand_slots(&b->demand, 6);
    stats->tree_demand_sum_maxgen = c5_demand_sum_maxgen(&b->demand);
    stats->tree_tags = b->tree->tags;
    stats->tree_reads = b->tree->reads;
    stats->tree_writes = b->tree->writes;
    if (b->sdram) {
        const c5_sdram_tree *t = b->sdram;
        stats->tree_sdram = 1;
        stats->tree_nodes = t->t.n;
        stats->tree_slots = (uint32_t)t->slots;
        stats->tree_overflow = t->overflow || t->t.oom;
        stats->tree_tags = t->tags;
        stats->tree_reads = t->reads + t->dir_reads;
        stats->tree_writes = t->writes;
        stats->tree_sdram_bytes = c5_sdram_tree_bytes_used(t);
        stats->tree_cell_nodes_max = t->max_index;
    }
    stats->cycles = stats->cycles_process + stats->cycles_fetch;
    stats->board_s = (double)stats->cycles / C5_BD_CLOCK_HZ;
}
