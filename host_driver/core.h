/* Inside the driver: the handle and the packet link that core.c gives frame.c. Not part of
 * the public API (c5drv.h). */
#ifndef C5_DRV_CORE_H
#define C5_DRV_CORE_H

#include <stdint.h>

#include "c5drv.h"
#include "hostmem.h"
#include "tlp.h"

typedef enum { DRV_IDLE, DRV_RUNNING, DRV_DONE } drv_state;

struct c5drv {
    c5drv_transport t;
    char msg[512];
    uint8_t *rx, *tx;       /* one packet each way, C5_TLP_MAX_BYTES */
    uint8_t tag;            /* next register access's tag */
    int gone;               /* the board went away: every later call fails at once */
    int loaded;             /* hm holds a scene */
    c5_hostmem hm;
    drv_state state;
    int frame;              /* the frame started last */
    uint32_t irq;           /* interrupt bits received and not handled yet */
    c5drv_counters cnt;     /* the driver's side of the current/last frame */
    double t_start;         /* start_frame, monotonic seconds */
    uint64_t ur_addr;       /* last dma_read refused with UR (named when the board then faults) */
    int ur_seen;
    /* the cell being uploaded, for cell_upload_s */
    int up_active;
    uint64_t up_addr, up_end, up_left;
    double up_t0;
};

/* Monotonic seconds. */
double drv_now(void);
/* Sets the handle's message and returns code. */
int drv_fail(c5drv *d, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* Starts a public call: clears the message, refuses a handle whose board went away. */
int drv_begin(c5drv *d);

/* Register access; other packets arriving meanwhile are served or queued (drv_pump). Each
 * receive waits at most C5DRV_IO_TIMEOUT_MS, and never past deadline (monotonic seconds,
 * 0: none). */
int drv_reg_read(c5drv *d, uint32_t off, uint32_t *val, double deadline);
int drv_reg_write(c5drv *d, uint32_t off, uint32_t val, double deadline);

/* Receives one packet (waiting at most ms) and handles it: dma_read served, dma_write
 * stored, interrupt bits added to d->irq. A reg_completion is garbage here (no register
 * access is outstanding). C5DRV_E_TIMEOUT when nothing arrived. */
int drv_pump(c5drv *d, unsigned ms);

#endif
