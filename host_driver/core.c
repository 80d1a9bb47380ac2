/* The driver's handle and its packet link (docs/host-protocol.md): sending with stall
 * recovery, receiving through c5_tlp_check, serving the board's DMA from host memory, and
 * register access with one outstanding tag. The frame sequence is frame.c's. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "c5_regs_map.h"
#include "core.h"

double drv_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int drv_fail(c5drv *d, int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->msg, sizeof d->msg, fmt, ap);
    va_end(ap);
    return code;
}

int drv_begin(c5drv *d)
{
    d->msg[0] = '\0';
    if (d->gone)
        return drv_fail(d, C5DRV_E_DISCONNECTED, "the board went away; close the handle and open it again");
    return C5DRV_OK;
}

/* A transport error: the transport wrote its message; a disconnect ends the frame for good. */
static int link_error(c5drv *d, int rc)
{
    if (rc == C5DRV_E_DISCONNECTED) {
        d->gone = 1;
        d->state = DRV_IDLE;
        d->up_active = 0;
    }
    if (!d->msg[0])
        snprintf(d->msg, sizeof d->msg, "%s", c5drv_strerror(rc));
    return rc;
}

static void put_le32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t get_le32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* One transfer with the stall rule: clear the halt and retry the same transfer, at most
 * C5DRV_STALL_RETRIES times. in selects recv (into d->rx) or send (d->tx, len bytes). */
static int transfer(c5drv *d, int in, size_t len, size_t *got, unsigned ms)
{
    for (int clears = 0;; clears++) {
        d->msg[0] = '\0';
        int rc = in ? d->t.recv(d->t.ctx, d->rx, C5_TLP_MAX_BYTES, got, ms, d->msg, sizeof d->msg)
                    : d->t.send(d->t.ctx, d->tx, len, ms, d->msg, sizeof d->msg);
        if (rc == C5DRV_OK) {
            d->cnt.stall_retries += (uint64_t)clears; /* these clear-halts recovered the endpoint */
            return rc;
        }
        if (rc != C5DRV_E_STALL)
            return link_error(d, rc);
        if (clears == C5DRV_STALL_RETRIES)
            return drv_fail(d, C5DRV_E_STALL, "%s endpoint still stalled after %d clear-halts", in ? "IN" : "OUT",
                            C5DRV_STALL_RETRIES);
        d->msg[0] = '\0';
        int hc = d->t.clear_halt(d->t.ctx, in, d->msg, sizeof d->msg);
        if (hc != C5DRV_OK)
            return link_error(d, hc);
    }
}

static int send_pkt(c5drv *d, size_t len) { return transfer(d, 0, len, NULL, C5DRV_IO_TIMEOUT_MS); }

/* Answers a dma_read from host memory: one completion with all the data, or UR with no
 * payload when the range is not wholly inside one buffer (the board then faults). */
static int serve_read(c5drv *d, const c5_tlp_header_t *h)
{
    uint64_t addr = (uint64_t)h->addr_hi << 32 | h->addr_lo;
    size_t len = h->length;
    const c5_hm_buf *b = d->loaded ? c5_hostmem_find(&d->hm, addr, len) : NULL;
    if (!b) {
        d->ur_addr = addr;
        d->ur_seen = 1;
        return send_pkt(d, c5_tlp_put(d->tx, C5_TLP_DMA_COMPLETION, (uint8_t)h->tag, C5_TLP_UR, 0, addr));
    }
    size_t n = c5_tlp_put(d->tx, C5_TLP_DMA_COMPLETION, (uint8_t)h->tag, C5_TLP_SC, (uint32_t)len, addr);
    memcpy(d->tx + C5_TLP_HEADER_BYTES, b->data + (addr - b->addr), len);
    int rc = send_pkt(d, n);
    if (rc != C5DRV_OK)
        return rc;
    d->cnt.dma_reads++;
    d->cnt.bytes_served += len;
    if (d->up_active && addr >= d->up_addr && addr + len <= d->up_end) {
        d->cnt.cell_bytes += len;
        d->up_left = d->up_left > len ? d->up_left - len : 0;
        if (!d->up_left) {
            d->cnt.cell_upload_s += drv_now() - d->up_t0;
            d->up_active = 0;
        }
    }
    return C5DRV_OK;
}

/* A posted dma_write: only the frame buffer may be written. */
static int store_write(c5drv *d, const c5_tlp_header_t *h)
{
    uint64_t addr = (uint64_t)h->addr_hi << 32 | h->addr_lo;
    const c5_hm_buf *b = d->loaded ? c5_hostmem_find(&d->hm, addr, h->length) : NULL;
    if (!b || b != &d->hm.fb)
        return drv_fail(d, C5DRV_E_PROTOCOL, "dma_write of %u bytes at 0x%llx: outside the frame buffer",
                        (unsigned)h->length, (unsigned long long)addr);
    memcpy(b->data + (addr - b->addr), d->rx + C5_TLP_HEADER_BYTES, h->length);
    d->cnt.fb_bytes += h->length;
    return C5DRV_OK;
}

/* Receives and checks one packet; handles all but a reg_completion, which it returns with 1
 * when want_tag >= 0 and the tag matches. */
static int pump_one(c5drv *d, unsigned ms, int want_tag, c5_tlp_header_t *h)
{
    size_t got = 0;
    int rc = transfer(d, 1, 0, &got, ms);
    if (rc != C5DRV_OK)
        return rc;
    char why[256];
    int ck = c5_tlp_check(d->rx, got, h, why, sizeof why);
    if (ck == C5_TLP_SHORT)
        return drv_fail(d, C5DRV_E_SHORT, "from the board: %s", why);
    if (ck != 0)
        return drv_fail(d, C5DRV_E_PROTOCOL, "from the board: %s", why);
    switch (h->type) {
    case C5_TLP_REG_COMPLETION:
        if (want_tag < 0)
            return drv_fail(d, C5DRV_E_PROTOCOL, "reg_completion with tag %u while no register access is outstanding",
                            (unsigned)h->tag);
        if ((int)h->tag != want_tag)
            return drv_fail(d, C5DRV_E_PROTOCOL, "reg_completion with tag %u, expected %d", (unsigned)h->tag,
                            want_tag);
        return 1;
    case C5_TLP_DMA_READ:
        return serve_read(d, h);
    case C5_TLP_DMA_WRITE:
        return store_write(d, h);
    case C5_TLP_INTERRUPT:
        d->irq |= get_le32(d->rx + C5_TLP_HEADER_BYTES);
        d->cnt.interrupts++;
        return C5DRV_OK;
    default:
        return drv_fail(d, C5DRV_E_PROTOCOL, "%s from the board: only the host sends those",
                        c5_tlp_type_name(h->type));
    }
}

int drv_pump(c5drv *d, unsigned ms)
{
    c5_tlp_header_t h;
    int rc = pump_one(d, ms, -1, &h);
    if (rc == C5DRV_E_TIMEOUT)
        d->msg[0] = '\0'; /* the caller decides whether silence is an error */
    return rc;
}

/* Milliseconds one receive may wait: C5DRV_IO_TIMEOUT_MS, less when the deadline is nearer;
 * 0 when it has passed. */
static unsigned io_ms(double deadline)
{
    if (deadline <= 0)
        return C5DRV_IO_TIMEOUT_MS;
    double left = (deadline - drv_now()) * 1e3;
    if (left <= 0)
        return 0;
    return left < C5DRV_IO_TIMEOUT_MS ? (unsigned)left + 1 : C5DRV_IO_TIMEOUT_MS;
}

static int reg_access(c5drv *d, int write, uint32_t off, uint32_t val, uint32_t *out, double deadline)
{
    const char *what = write ? "reg_write" : "reg_read";
    if (off % 4 || off >= C5_REG_BAR0_BYTES)
        return drv_fail(d, C5DRV_E_ARG, "%s 0x%x: BAR0 holds %d bytes of 4-byte registers", what, (unsigned)off,
                        C5_REG_BAR0_BYTES);
    uint8_t tag = d->tag++;
    size_t n = c5_tlp_put(d->tx, write ? C5_TLP_REG_WRITE : C5_TLP_REG_READ, tag, C5_TLP_SC, 4, off);
    if (write)
        put_le32(d->tx + C5_TLP_HEADER_BYTES, val);
    int rc = send_pkt(d, n);
    if (rc != C5DRV_OK)
        return rc;
    c5_tlp_header_t h;
    for (;;) {
        unsigned ms = io_ms(deadline);
        rc = ms ? pump_one(d, ms, tag, &h) : C5DRV_E_TIMEOUT;
        if (rc == 1)
            break;
        if (rc == C5DRV_E_TIMEOUT)
            return drv_fail(d, rc, "no reg_completion for %s 0x%03x within %u ms", what, (unsigned)off,
                            ms ? ms : 0u);
        if (rc != C5DRV_OK)
            return rc;
    }
    if (h.status != C5_TLP_SC)
        return drv_fail(d, h.status == C5_TLP_UR ? C5DRV_E_ARG : C5DRV_E_PROTOCOL, "%s 0x%03x: the board answered %s",
                        what, (unsigned)off,
                        h.status == C5_TLP_UR ? "UR (no such register)" : "CA (a malformed request)");
    if (h.addr_lo != off || h.length != (write ? 0u : 4u))
        return drv_fail(d, C5DRV_E_PROTOCOL, "%s 0x%03x: completion for 0x%03x with %u bytes", what, (unsigned)off,
                        (unsigned)h.addr_lo, (unsigned)h.length);
    if (!write)
        *out = get_le32(d->rx + C5_TLP_HEADER_BYTES);
    return C5DRV_OK;
}

int drv_reg_read(c5drv *d, uint32_t off, uint32_t *val, double deadline)
{
    return reg_access(d, 0, off, 0, val, deadline);
}

int drv_reg_write(c5drv *d, uint32_t off, uint32_t val, double deadline)
{
    return reg_access(d, 1, off, val, NULL, deadline);
}

/* ---- the public calls that are not the frame's -------------------------------------------- */

int c5drv_open(const c5drv_transport *t, c5drv **out, char *msg, size_t cap)
{
    *out = NULL;
    if (!t || !t->send || !t->recv || !t->clear_halt) {
        if (t && t->close)
            t->close(t->ctx);
        snprintf(msg, cap, "c5drv_open: a transport needs send, recv and clear_halt");
        return C5DRV_E_ARG;
    }
    c5drv *d = calloc(1, sizeof *d);
    uint8_t *rx = malloc(C5_TLP_MAX_BYTES), *tx = malloc(C5_TLP_MAX_BYTES);
    if (!d || !rx || !tx) {
        free(d);
        free(rx);
        free(tx);
        if (t->close)
            t->close(t->ctx);
        snprintf(msg, cap, "out of memory for the driver handle");
        return C5DRV_E_NOMEM;
    }
    d->t = *t;
    d->rx = rx;
    d->tx = tx;
    *out = d;
    if (cap)
        msg[0] = '\0';
    return C5DRV_OK;
}

void c5drv_close(c5drv *d)
{
    if (!d)
        return;
    if (d->t.close)
        d->t.close(d->t.ctx);
    if (d->loaded)
        c5_hostmem_free(&d->hm);
    free(d->rx);
    free(d->tx);
    free(d);
}

const char *c5drv_strerror(int code)
{
    switch (code) {
    case C5DRV_OK: return "success";
    case C5DRV_E_ARG: return "bad argument";
    case C5DRV_E_NOT_FOUND: return "no such board";
    case C5DRV_E_ACCESS: return "board cannot be opened or claimed";
    case C5DRV_E_IO: return "transport error";
    case C5DRV_E_TIMEOUT: return "board did not answer in time";
    case C5DRV_E_STALL: return "endpoint stalled";
    case C5DRV_E_SHORT: return "short transfer";
    case C5DRV_E_DISCONNECTED: return "board disconnected";
    case C5DRV_E_PROTOCOL: return "protocol error";
    case C5DRV_E_BOARD: return "board reported an error";
    case C5DRV_E_VERSION: return "not a cube5 board or unknown register map version";
    case C5DRV_E_STATE: return "call out of order";
    case C5DRV_E_NOMEM: return "out of memory";
    case C5DRV_E_SCENE: return "scene cannot be loaded";
    default: return "unknown error";
    }
}

const char *c5drv_message(const c5drv *d) { return d ? d->msg : ""; }

int c5drv_reg_read(c5drv *d, uint32_t offset, uint32_t *value)
{
    int rc = drv_begin(d);
    return rc ? rc : drv_reg_read(d, offset, value, 0);
}

int c5drv_reg_write(c5drv *d, uint32_t offset, uint32_t value)
{
    int rc = drv_begin(d);
    return rc ? rc : drv_reg_write(d, offset, value, 0);
}

int c5drv_identify(c5drv *d, c5drv_info *info)
{
    int rc = drv_begin(d);
    uint32_t id = 0, ver = 0;
    if (rc || (rc = drv_reg_read(d, C5_REG_ID_OFFSET, &id, 0)) || (rc = drv_reg_read(d, C5_REG_VERSION_OFFSET, &ver, 0)))
        return rc;
    memset(info, 0, sizeof *info);
    info->id = id;
    info->major = c5_reg_version_get_major(ver);
    info->minor = c5_reg_version_get_minor(ver);
    const char *serial = d->t.serial ? d->t.serial(d->t.ctx) : NULL;
    snprintf(info->serial, sizeof info->serial, "%s", serial ? serial : "");
    if (id != C5_REG_ID_RESET)
        return drv_fail(d, C5DRV_E_VERSION, "not a cube5 board: id 0x%08x, expected 0x%08x", (unsigned)id,
                        C5_REG_ID_RESET);
    if (info->major != C5_REG_VERSION_MAJOR_RESET)
        return drv_fail(d, C5DRV_E_VERSION, "register map %u.%u: this driver knows major %u only", info->major,
                        info->minor, (unsigned)C5_REG_VERSION_MAJOR_RESET);
    return C5DRV_OK;
}

int c5drv_reset(c5drv *d)
{
    int rc = drv_begin(d);
    if (rc)
        return rc;
    /* whatever happens, the frame this handle knew of is abandoned */
    d->state = DRV_IDLE;
    d->irq = 0;
    d->up_active = 0;
    return drv_reg_write(d, C5_REG_CONTROL_OFFSET, c5_reg_control_set_reset(0, 1), 0);
}
