/* Harness: the driver's handling of what the board sends (host_driver/core.c, frame.c): a
 * whole frame (identify, load a small scene, start, wait, read the image and counters) over
 * a transport whose IN side plays back the input. The input is a list of records
 * [kind][len_lo][len_hi][len bytes]; kind % 6 chooses what the next receive gets:
 *   0  the bytes as they are (any packet, or garbage);
 *   1  a register completion for the last register access sent (status and value from the
 *      bytes), so that the fuzzer gets past the register traffic;
 *   2  an interrupt whose bits are the first 4 bytes;
 *   3  a dma_read of one of the driver's buffers (which: byte 0; offset and length: 1..4);
 *   4  a dma_write into the frame buffer (offset: bytes 0..1; payload: the rest);
 *   5  a transport error (stall, timeout, short, I/O, disconnect: byte 0).
 * When the records run out, the board is gone (C5DRV_E_DISCONNECTED). Promises: every call
 * returns a c5drv status with a message on failure; no hang (each receive takes a record). */
#include "c5drv.h"
#include "core.h"
#include "fuzz.h"

typedef struct {
    const uint8_t *p;
    size_t n;
    c5_tlp_header_t last;   /* the last packet the driver sent */
    int have_last;
    c5drv *d;
} feed;

static int f_send(void *ctx, const uint8_t *pkt, size_t len, unsigned ms, char *msg, size_t cap)
{
    (void)ms, (void)msg, (void)cap;
    feed *f = ctx;
    char why[128];
    /* the driver must only ever send well-formed packets */
    c5_fuzz_expect(c5_tlp_check(pkt, len, &f->last, why, sizeof why) == 0, "the driver sends valid packets");
    f->have_last = 1;
    return C5DRV_OK;
}

static void le32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t take32(const uint8_t *p, size_t n, size_t at)
{
    uint32_t v = 0;
    for (size_t i = 0; i < 4; i++)
        v |= (uint32_t)(at + i < n ? p[at + i] : 0) << (8 * i);
    return v;
}

static const c5_hm_buf *pick_buf(const c5drv *d, unsigned k)
{
    if (!d || !d->loaded)
        return NULL;
    const c5_hostmem *m = &d->hm;
    unsigned nb = 2 + (unsigned)(m->has_volume ? m->ncells : 0);
    k %= nb;
    return k == 0 ? &m->desc : k == 1 ? &m->fb : &m->cell[k - 2];
}

static int f_recv(void *ctx, uint8_t *buf, size_t cap, size_t *got, unsigned ms, char *msg, size_t mcap)
{
    (void)ms;
    feed *f = ctx;
    *got = 0;
    if (f->n < 3) {
        snprintf(msg, mcap, "fuzz: records ran out");
        return C5DRV_E_DISCONNECTED;
    }
    unsigned kind = f->p[0] % 6;
    size_t len = (size_t)f->p[1] | (size_t)f->p[2] << 8;
    if (len > f->n - 3)
        len = f->n - 3;
    const uint8_t *r = f->p + 3;
    f->p += 3 + len;
    f->n -= 3 + len;
    switch (kind) {
    case 0:
        if (len > cap)
            len = cap;
        memcpy(buf, r, len);
        *got = len;
        return C5DRV_OK;
    case 1: {
        if (!f->have_last)
            return C5DRV_E_TIMEOUT;
        c5_tlp_status st = len && r[0] % 3 == 1 ? C5_TLP_UR : len && r[0] % 3 == 2 ? C5_TLP_CA : C5_TLP_SC;
        int data = f->last.type == C5_TLP_REG_READ && st == C5_TLP_SC;
        *got = c5_tlp_put(buf, C5_TLP_REG_COMPLETION, (uint8_t)f->last.tag, st, data ? 4 : 0, f->last.addr_lo);
        if (data)
            le32(buf + C5_TLP_HEADER_BYTES, take32(r, len, 1));
        return C5DRV_OK;
    }
    case 2:
        *got = c5_tlp_put(buf, C5_TLP_INTERRUPT, 0, C5_TLP_SC, 4, 0);
        le32(buf + C5_TLP_HEADER_BYTES, take32(r, len, 0));
        return C5DRV_OK;
    case 3: {
        const c5_hm_buf *b = pick_buf(f->d, len ? r[0] : 0);
        uint64_t addr = b ? b->addr : 0x100000000ull;
        uint32_t off = (take32(r, len, 1) & 0xffffu) * 4, n = ((take32(r, len, 1) >> 16) % 1024 + 1) * 4;
        *got = c5_tlp_put(buf, C5_TLP_DMA_READ, len > 5 ? r[5] : 0, C5_TLP_SC, n, addr + off);
        return C5DRV_OK;
    }
    case 4: {
        const c5_hm_buf *b = pick_buf(f->d, 1);
        uint64_t addr = (b ? b->addr : 0x200000000ull) + (uint64_t)(take32(r, len, 0) & 0xffffu) * 4;
        size_t n = len > 2 ? (len - 2) / 4 * 4 : 0;
        if (n == 0 || n > C5_TLP_MAX_PAYLOAD)
            n = 4;
        *got = c5_tlp_put(buf, C5_TLP_DMA_WRITE, 0, C5_TLP_SC, (uint32_t)n, addr);
        memset(buf + C5_TLP_HEADER_BYTES, 0, n);
        if (len > 2)
            memcpy(buf + C5_TLP_HEADER_BYTES, r + 2, len - 2 < n ? len - 2 : n);
        return C5DRV_OK;
    }
    default: {
        static const int errs[] = {C5DRV_E_STALL, C5DRV_E_TIMEOUT, C5DRV_E_SHORT, C5DRV_E_IO, C5DRV_E_DISCONNECTED};
        snprintf(msg, mcap, "fuzz: transport error");
        return errs[(len ? r[0] : 0) % 5];
    }
    }
}

static int f_clear_halt(void *ctx, int in, char *msg, size_t cap)
{
    (void)ctx, (void)in, (void)msg, (void)cap;
    return C5DRV_OK;
}

/* A scene with a small volume, split into 2 cells, on a 4x4 image: cheap to load on
 * every input, and with cells for the board to fetch. */
static const char SCENE[] =
    "{\"grid\": {\"center\": [0, 0, 0], \"size\": 8},"
    " \"volumes\": [{\"generator\": \"blobs\", \"dims\": [8, 8, 8], \"count\": 2, \"seed\": 1}],"
    " \"transfer_function\": {\"opacity\": [[0, 0], [255, 0.5]], \"color\": [[0, 1, 1, 1]]},"
    " \"camera\": {\"eye\": [0, 20, 0], \"target\": [0, 0, 0], \"width\": 4, \"height\": 4}}";

static void expect_status(const c5drv *d, int rc)
{
    c5_fuzz_expect(rc <= 0 && rc >= C5DRV_E_SCENE, "a c5drv status");
    if (rc != C5DRV_OK)
        c5_fuzz_expect(c5drv_message(d)[0] != 0, "a failed call says why");
}

/* One handle for the whole run, the scene loaded once (loading costs far more than a frame):
 * each input starts from the state a fresh handle with that scene has. The driver never
 * writes the scene's buffers, and start_frame clears the frame buffer, so inputs do not
 * see each other. */
static feed f;
static c5drv *d;

static void fresh(void)
{
    if (!d) {
        c5drv_transport t = {.ctx = &f, .send = f_send, .recv = f_recv, .clear_halt = f_clear_halt};
        char msg[256];
        c5_fuzz_expect(c5drv_open(&t, &d, msg, sizeof msg) == C5DRV_OK, "c5drv_open on a complete transport");
        int rc = c5drv_load_scene(d, SCENE, NULL, "fuzz scene", (const int[3]){2, 1, 1}, 4, 4);
        c5_fuzz_expect(rc == C5DRV_OK, "the fuzz scene loads");
        f.d = d;
    }
    d->msg[0] = 0;
    d->tag = 0;
    d->gone = 0;
    d->state = DRV_IDLE;
    d->frame = 0;
    d->irq = 0;
    memset(&d->cnt, 0, sizeof d->cnt);
    d->t_start = 0;
    d->ur_addr = 0;
    d->ur_seen = 0;
    d->up_active = 0;
    d->up_addr = d->up_end = d->up_left = 0;
    d->up_t0 = 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fresh();
    f.p = data;
    f.n = size;
    f.have_last = 0;
    c5drv_info info;
    expect_status(d, c5drv_identify(d, &info));
    int rc;
    for (int frame = 0; frame < 2 && f.n >= 3; frame++) {
        expect_status(d, rc = c5drv_start_frame(d, 0));
        if (rc == C5DRV_OK)
            expect_status(d, rc = c5drv_wait_frame(d, 2000));
        if (rc == C5DRV_OK) {
            c5drv_image img;
            expect_status(d, rc = c5drv_read_frame(d, &img));
            if (rc == C5DRV_OK)
                c5drv_image_free(&img);
        }
        c5drv_counters c;
        expect_status(d, c5drv_read_counters(d, &c));
        expect_status(d, c5drv_reset(d));
    }
    return 0;
}
