/* What emu_board.c (registers, packets, faults) and emu_frame.c (the frame thread) share.
 * One mutex guards all of it; the frame thread holds it only between model calls. */
#ifndef C5_EMU_INTERNAL_H
#define C5_EMU_INTERNAL_H

#include <pthread.h>
#include <stdint.h>

#include "c5_regs_map.h"
#include "emu_board.h"
#include "tlp.h"

typedef struct c5_emu_pkt {
    struct c5_emu_pkt *next;
    int checked;            /* counted by the fault injector */
    c5_fault_kind fault;    /* the fault this packet carries */
    unsigned type;
    size_t len;
    uint8_t data[];
} c5_emu_pkt;

typedef struct {
    int active;
    uint64_t addr;
    uint32_t len, got;
    uint8_t *dst;
} c5_emu_read; /* a dma_read in flight, by tag */

struct c5_emu {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    char serial[64];
    uint32_t regs[C5_REG_BAR0_BYTES / 4];
    uint64_t cycles, samples;            /* 64-bit counters behind the _lo/_hi pairs */
    uint32_t cycles_hi_latch, samples_hi_latch;
    /* IN queue */
    c5_emu_pkt *in_head, *in_tail;
    int pending_notify;
    void (*notify)(void *);
    void *notify_ctx;
    /* faults */
    c5_fault fault;
    unsigned fault_count, stalls_left;
    int silent, gone;
    uint64_t refused;                    /* malformed or misdirected packets from the host */
    /* the frame thread */
    pthread_t thread;
    int thread_live;                     /* started and not yet joined */
    int thread_done;                     /* it has published its frame and is returning */
    int abandon;                         /* reset or free: the running frame stops at its next wait */
    unsigned generation;                 /* frames started; a stale thread leaves registers alone */
    /* DMA */
    int doorbell;
    uint64_t db_addr;
    uint32_t db_len, db_cell;
    c5_emu_read rd[256];
    unsigned reads_outstanding;
    uint8_t next_tag;
    const char *dma_error;               /* why the DMA failed, NULL while it works */
    /* the model's account of the last completed frame */
    c5_board_stats last;
    int have_last;
};

/* Queues a packet to the host (the caller holds the lock; the transport is notified when it
 * is released with c5_emu_unlock). */
int c5_emu_send_locked(c5_emu *e, c5_tlp_type type, uint8_t tag, c5_tlp_status status, uint32_t length,
                       uint64_t addr, const void *payload);
void c5_emu_unlock(c5_emu *e);
/* Sets int_status bits and sends an interrupt message when one of them is unmasked. */
void c5_emu_raise_locked(c5_emu *e, uint32_t bits);

/* emu_frame.c: control.start_frame (ignored while busy), control.reset / free (the running
 * frame is told to stop; it is joined later, never under the lock), and the join. */
void c5_emu_start_locked(c5_emu *e);
void c5_emu_abandon_locked(c5_emu *e);
void c5_emu_join(c5_emu *e);

#endif
