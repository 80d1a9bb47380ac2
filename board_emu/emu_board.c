/* The emulated board (emu_board.h): BAR0 register file, the link's packets, interrupts and
 * the fault injector. The frame itself runs on its own thread (emu_frame.c). */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "c5_regs_map.h"
#include "emu_internal.h"

/* ---- the IN queue ----------------------------------------------------------------------- */

int c5_emu_send_locked(c5_emu *e, c5_tlp_type type, uint8_t tag, c5_tlp_status status, uint32_t length,
                       uint64_t addr, const void *payload)
{
    size_t pay = c5_tlp_payload_bytes(&(c5_tlp_header_t){.type = type, .status = status, .length = length});
    c5_emu_pkt *p = malloc(sizeof *p + C5_TLP_HEADER_BYTES + pay);
    if (!p)
        return -1;
    p->next = NULL;
    p->checked = 0;
    p->fault = C5_FAULT_NONE;
    p->type = type;
    p->len = c5_tlp_put(p->data, type, tag, status, length, addr);
    if (pay)
        memcpy(p->data + C5_TLP_HEADER_BYTES, payload, pay);
    if (e->in_tail)
        e->in_tail->next = p;
    else
        e->in_head = p;
    e->in_tail = p;
    pthread_cond_broadcast(&e->cv);
    e->pending_notify = 1;
    return 0;
}

/* Calls the transport's notify after the lock is released (it may take its own locks);
 * the callback is read while the lock is still held. */
void c5_emu_unlock(c5_emu *e)
{
    void (*fn)(void *) = e->pending_notify ? e->notify : NULL;
    void *ctx = e->notify_ctx;
    e->pending_notify = 0;
    pthread_mutex_unlock(&e->mu);
    if (fn)
        fn(ctx);
}

static void drop_in_queue(c5_emu *e)
{
    for (c5_emu_pkt *p = e->in_head, *n; p; p = n) {
        n = p->next;
        free(p);
    }
    e->in_head = e->in_tail = NULL;
}

/* ---- registers -------------------------------------------------------------------------- */

typedef struct {
    uint32_t offset, reset, rw, w1c, wo;
} reg_desc;

#define REG_DESC(name, off, reset, rw, w1c, wo) {off, reset, rw, w1c, wo},
static const reg_desc REGS[] = {C5_REGS_ACCESS(REG_DESC)};
#define N_REGS (sizeof REGS / sizeof REGS[0])

static const reg_desc *reg_at(uint32_t offset)
{
    if (offset % 4 || offset >= C5_REG_BAR0_BYTES)
        return NULL;
    for (size_t i = 0; i < N_REGS; i++)
        if (REGS[i].offset == offset)
            return &REGS[i];
    return NULL;
}

static void regs_reset(c5_emu *e)
{
    memset(e->regs, 0, sizeof e->regs);
    for (size_t i = 0; i < N_REGS; i++)
        e->regs[REGS[i].offset / 4] = REGS[i].reset;
    e->cycles = e->samples = 0;
    e->cycles_hi_latch = e->samples_hi_latch = 0;
    e->doorbell = 0;
}

/* An interrupt message: the sources now pending and not masked. */
static void send_interrupt_locked(c5_emu *e)
{
    uint32_t v = e->regs[C5_REG_INT_STATUS_OFFSET / 4] & ~e->regs[C5_REG_INT_MASK_OFFSET / 4];
    uint8_t le[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    c5_emu_send_locked(e, C5_TLP_INTERRUPT, 0, C5_TLP_SC, 4, 0, le);
}

static int int_enabled(const c5_emu *e) { return c5_reg_control_get_int_enable(e->regs[C5_REG_CONTROL_OFFSET / 4]); }

/* Interrupt sources rose (int_status bits): a message when one of them is not masked. */
void c5_emu_raise_locked(c5_emu *e, uint32_t bits)
{
    e->regs[C5_REG_INT_STATUS_OFFSET / 4] |= bits;
    if (bits & ~e->regs[C5_REG_INT_MASK_OFFSET / 4] && int_enabled(e))
        send_interrupt_locked(e);
}

static uint32_t reg_read(c5_emu *e, uint32_t off)
{
    switch (off) {
    case C5_REG_CNT_CYCLES_LO_OFFSET:
        e->cycles_hi_latch = (uint32_t)(e->cycles >> 32);
        return (uint32_t)e->cycles;
    case C5_REG_CNT_CYCLES_HI_OFFSET:
        return e->cycles_hi_latch;
    case C5_REG_CNT_SAMPLES_LO_OFFSET:
        e->samples_hi_latch = (uint32_t)(e->samples >> 32);
        return (uint32_t)e->samples;
    case C5_REG_CNT_SAMPLES_HI_OFFSET:
        return e->samples_hi_latch;
    default:
        return e->regs[off / 4];
    }
}

static void reg_write(c5_emu *e, const reg_desc *r, uint32_t v)
{
    uint32_t *w = &e->regs[r->offset / 4];
    uint32_t before_visible = e->regs[C5_REG_INT_STATUS_OFFSET / 4] & ~e->regs[C5_REG_INT_MASK_OFFSET / 4];
    int before_enable = int_enabled(e);
    *w = (*w & ~r->rw) | (v & r->rw);
    *w &= ~(v & r->w1c);
    uint32_t act = v & r->wo;
    if (r->offset == C5_REG_CONTROL_OFFSET) {
        if (act & C5_REG_CONTROL_RESET_MASK) {
            c5_emu_abandon_locked(e);
            drop_in_queue(e);
            regs_reset(e);
            return;
        }
        if (act & C5_REG_CONTROL_START_FRAME_MASK)
            c5_emu_start_locked(e);
    } else if (r->offset == C5_REG_DMA_DOORBELL_OFFSET && (act & C5_REG_DMA_DOORBELL_RING_MASK)) {
        e->doorbell = 1;
        e->db_addr = (uint64_t)e->regs[C5_REG_DMA_ADDR_HI_OFFSET / 4] << 32 | e->regs[C5_REG_DMA_ADDR_LO_OFFSET / 4];
        e->db_len = e->regs[C5_REG_DMA_LENGTH_OFFSET / 4];
        e->db_cell = c5_reg_dma_cell_get_cell(e->regs[C5_REG_DMA_CELL_OFFSET / 4]);
        pthread_cond_broadcast(&e->cv);
    }
    /* Unmasking or enabling with sources pending makes them visible: one message for them
     * (a level-triggered INTA# would assert at this moment too). */
    uint32_t visible = e->regs[C5_REG_INT_STATUS_OFFSET / 4] & ~e->regs[C5_REG_INT_MASK_OFFSET / 4];
    if (int_enabled(e) && visible && (visible & ~before_visible || !before_enable))
        send_interrupt_locked(e);
}

/* ---- packets from the host -------------------------------------------------------------- */

/* A dma_completion: data for an outstanding dma_read, in address order. */
static void dma_completion(c5_emu *e, const c5_tlp_header_t *h, const uint8_t *data)
{
    c5_emu_read *r = &e->rd[h->tag];
    uint64_t addr = (uint64_t)h->addr_hi << 32 | h->addr_lo;
    if (!r->active) {
        e->dma_error = "a dma_completion whose tag has no read outstanding";
    } else if (h->status != C5_TLP_SC) {
        e->dma_error = h->status == C5_TLP_UR ? "the host refused a dma_read (unsupported request: address outside "
                                                "host memory)"
                                              : "the host aborted a dma_read (completer abort)";
    } else if (addr != r->addr + r->got || h->length > r->len - r->got) {
        e->dma_error = "a dma_completion outside its request (address or length)";
    } else {
        memcpy(r->dst + r->got, data, h->length);
        r->got += h->length;
        if (r->got < r->len)
            return;
    }
    if (r->active) {
        r->active = 0;
        e->reads_outstanding--;
    }
    pthread_cond_broadcast(&e->cv);
}

int c5_emu_out(c5_emu *e, const uint8_t *buf, size_t len)
{
    pthread_mutex_lock(&e->mu);
    if (e->gone) {
        c5_emu_unlock(e);
        return C5_EMU_GONE;
    }
    c5_tlp_header_t h;
    char why[160];
    int rc = c5_tlp_check(buf, len, &h, why, sizeof why);
    uint32_t off = h.addr_lo;
    const reg_desc *r;
    if (rc != 0) {
        /* The tag of a register request that reached us whole can still be answered. */
        if (len >= C5_TLP_HEADER_BYTES && h.sync == C5_TLP_SYNC && (h.type == C5_TLP_REG_READ || h.type == C5_TLP_REG_WRITE))
            c5_emu_send_locked(e, C5_TLP_REG_COMPLETION, h.tag, C5_TLP_CA, 0, off & ~3u, NULL);
        e->refused++;
    } else if (h.type == C5_TLP_REG_READ || h.type == C5_TLP_REG_WRITE) {
        if (!(r = reg_at(off))) {
            c5_emu_send_locked(e, C5_TLP_REG_COMPLETION, h.tag, C5_TLP_UR, 0, off, NULL);
        } else if (h.type == C5_TLP_REG_READ) {
            uint32_t v = reg_read(e, off);
            uint8_t le[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
            c5_emu_send_locked(e, C5_TLP_REG_COMPLETION, h.tag, C5_TLP_SC, 4, off, le);
        } else {
            const uint8_t *p = buf + C5_TLP_HEADER_BYTES;
            uint8_t tag = h.tag;
            reg_write(e, r, (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24);
            /* after a reset the completion goes into the emptied queue */
            c5_emu_send_locked(e, C5_TLP_REG_COMPLETION, tag, C5_TLP_SC, 0, off, NULL);
        }
    } else if (h.type == C5_TLP_DMA_COMPLETION) {
        dma_completion(e, &h, buf + C5_TLP_HEADER_BYTES);
    } else {
        e->refused++; /* board -> host types coming the wrong way */
    }
    c5_emu_unlock(e);
    return 0;
}

/* ---- packets to the host, with the fault injector ---------------------------------------- */

int c5_emu_in_pop(c5_emu *e, uint8_t *buf, size_t cap, size_t *len)
{
    pthread_mutex_lock(&e->mu);
    int rc = C5_EMU_NOTHING;
    c5_emu_pkt *p = e->in_head;
    if (e->gone) {
        rc = C5_EMU_GONE;
    } else if (!e->silent && p) {
        if (!p->checked) {
            p->checked = 1;
            if (e->fault.kind != C5_FAULT_NONE && (e->fault.type == 0 || e->fault.type == p->type) &&
                ++e->fault_count == (e->fault.nth ? e->fault.nth : 1)) {
                p->fault = e->fault.kind;
                e->stalls_left = e->fault.repeat ? e->fault.repeat : 1;
            }
        }
        switch (p->fault) {
        case C5_FAULT_STALL:
            if (e->stalls_left) {
                e->stalls_left--;
                rc = C5_EMU_STALL;
            }
            break;
        case C5_FAULT_TIMEOUT:
            e->silent = 1;
            break;
        case C5_FAULT_DISCONNECT:
            e->gone = 1;
            rc = C5_EMU_GONE;
            pthread_cond_broadcast(&e->cv);
            e->pending_notify = 1;
            break;
        default:
            break;
        }
        if (rc == C5_EMU_NOTHING && !e->silent) {
            size_t n = p->fault == C5_FAULT_SHORT ? p->len / 2 : p->len;
            if (p->fault == C5_FAULT_CORRUPT) {
                p->data[1] ^= 0xFF; /* tag */
                p->data[3] ^= 0xFF; /* sync */
            }
            *len = n < cap ? n : cap;
            memcpy(buf, p->data, *len);
            e->in_head = p->next;
            if (!e->in_head)
                e->in_tail = NULL;
            free(p);
            rc = C5_EMU_PACKET;
        }
    }
    c5_emu_unlock(e);
    return rc;
}

int c5_emu_in_wait(c5_emu *e, unsigned timeout_ms)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += timeout_ms / 1000;
    until.tv_nsec += (long)(timeout_ms % 1000) * 1000000L;
    if (until.tv_nsec >= 1000000000L) {
        until.tv_sec++;
        until.tv_nsec -= 1000000000L;
    }
    pthread_mutex_lock(&e->mu);
    int ready;
    while (!(ready = e->gone || (e->in_head && !e->silent)))
        if (pthread_cond_timedwait(&e->cv, &e->mu, &until) != 0)
            break;
    ready = e->gone || (e->in_head && !e->silent);
    pthread_mutex_unlock(&e->mu);
    return ready;
}

void c5_emu_set_notify(c5_emu *e, void (*fn)(void *ctx), void *ctx)
{
    pthread_mutex_lock(&e->mu);
    e->notify = fn;
    e->notify_ctx = ctx;
    pthread_mutex_unlock(&e->mu);
}

void c5_emu_set_fault(c5_emu *e, const c5_fault *f)
{
    pthread_mutex_lock(&e->mu);
    e->fault = f ? *f : (c5_fault){0};
    e->fault_count = 0;
    e->stalls_left = 0;
    pthread_mutex_unlock(&e->mu);
}

int c5_emu_gone(const c5_emu *e)
{
    c5_emu *m = (c5_emu *)e;
    pthread_mutex_lock(&m->mu);
    int g = m->gone;
    pthread_mutex_unlock(&m->mu);
    return g;
}

int c5_emu_last_stats(c5_emu *e, c5_board_stats *st)
{
    pthread_mutex_lock(&e->mu);
    int ok = e->have_last;
    if (ok)
        *st = e->last;
    pthread_mutex_unlock(&e->mu);
    return ok ? 0 : -1;
}

/* ---- life ------------------------------------------------------------------------------- */

c5_emu *c5_emu_new(const char *serial)
{
    c5_emu *e = calloc(1, sizeof *e);
    if (!e)
        return NULL;
    pthread_mutex_init(&e->mu, NULL);
    pthread_cond_init(&e->cv, NULL);
    snprintf(e->serial, sizeof e->serial, "%s", serial ? serial : "C5EMU0001");
    regs_reset(e);
    return e;
}

const char *c5_emu_serial(const c5_emu *e) { return e->serial; }

void c5_emu_free(c5_emu *e)
{
    if (!e)
        return;
    pthread_mutex_lock(&e->mu);
    c5_emu_abandon_locked(e);
    pthread_mutex_unlock(&e->mu);
    c5_emu_join(e);
    drop_in_queue(e);
    pthread_cond_destroy(&e->cv);
    pthread_mutex_destroy(&e->mu);
    free(e);
}
