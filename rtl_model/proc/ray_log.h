/* A ray's run on one of the host's helper threads, recorded so that the board's thread can
 * replay it in the sorter's order (docs/board-model.md, "Host threads").
 *
 * c5_proc_run and c5_proc_new_ray are functions of the ray, the frame's registers and the
 * cell in RDRAM, but for three effects: the counters they add (sums: their order does not
 * matter), the rays and colours they hand on through c5_proc_io (in order), and the voxel
 * cache's state (whether a sample hits depends on the rays before it). A recording processor
 * adds the counters into its own c5_proc_stats and writes the other two into its recorder;
 * the log made from it, replayed on the board's processor, has the same effect on them as the
 * call, bit for bit. */
#ifndef C5_RAY_LOG_H
#define C5_RAY_LOG_H

#include <stddef.h>

#include "processor.h"

/* A cache access's tag (processor.c: 16 bits an axis, z y x) and a run length in its top 16
 * bits: after the first access of a run, the ray's own access has just put the tag in its
 * line, so the rest of the run hit. */
#define C5_RLOG_TAG_BITS 48
#define C5_RLOG_RUN_MAX 0xffffu

/* enqueue: the ray in its packet, packed on the helper's thread (the packet holds the cell and
 * the node too; beside it for the board's DSP, which reads them first). deliver: the pixel
 * and its colour. */
typedef struct {
    uint32_t kind; /* C5_RLOG_ENQUEUE or C5_RLOG_DELIVER */
    uint32_t shadow, cell, node;
    union {
        uint8_t pk[C5_PACKET_BYTES];
        struct {
            uint32_t u, v;
            int64_t rgb[3];
        } px;
    };
} c5_rlog_event;

enum { C5_RLOG_ENQUEUE, C5_RLOG_DELIVER };

typedef struct c5_ray_rec {
    uint64_t *acc;    /* cache runs: tag | length << C5_RLOG_TAG_BITS */
    c5_rlog_event *ev;
    uint32_t n_acc, cap_acc, n_ev, cap_ev;
    int oom;          /* an append ran out of memory: the log is incomplete */
    const c5_cells *cells; /* the split the packets' positions are relative to */
} c5_ray_rec;

/* w becomes a copy of p (registers, cells, RDRAM, active cell) that records into rec: no
 * taps, zero counters. */
void c5_rlog_recorder(c5_proc *w, const c5_proc *p, c5_ray_rec *rec);
/* Empties the recorder before a call. */
static inline void c5_rlog_begin(c5_ray_rec *rec) { rec->n_acc = rec->n_ev = 0, rec->oom = 0; }
/* The bytes of the log of what rec holds (a multiple of 8), and the log written to dst
 * (8-byte aligned). */
size_t c5_rlog_size(const c5_ray_rec *rec);
void c5_rlog_write(const c5_ray_rec *rec, void *dst);
/* The recorded call's effects on p: its cache runs, then its rays and colours through p->io
 * (a ray through enqueue_packet where p->io has it, else unpacked for enqueue). */
void c5_rlog_replay(c5_proc *p, const void *log);
void c5_rlog_free(c5_ray_rec *rec);

/* A cache access while recording (processor.c, cache_access). */
void c5_rlog_access_slow(c5_ray_rec *rec, uint64_t tag);
static inline void c5_rlog_access(c5_ray_rec *rec, uint64_t tag)
{
    uint64_t *last = rec->n_acc ? &rec->acc[rec->n_acc - 1] : NULL;
    if (last && (*last & ((1ull << C5_RLOG_TAG_BITS) - 1)) == tag && (*last >> C5_RLOG_TAG_BITS) < C5_RLOG_RUN_MAX)
        *last += 1ull << C5_RLOG_TAG_BITS;
    else
        c5_rlog_access_slow(rec, tag);
}

#endif
