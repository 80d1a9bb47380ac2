/* The emulated board's frame (docs/host-protocol.md, "A frame"): on its own thread, the DSP
 * reads the scene descriptor by DMA, the model renders with every cell fetched from the
 * host, and the frame buffer goes back by DMA. */
#include <stdlib.h>
#include <string.h>

#include "emu_internal.h"
#include "image.h"

#define ERR_SCENE 1u
#define ERR_DMA 3u

typedef struct {
    c5_emu *e;
    unsigned gen;
    uint32_t regs[C5_REG_BAR0_BYTES / 4]; /* as written before start_frame */
    uint32_t *fb;                         /* the frame buffer words, from the frame tap */
    int w, h;
    const char *dma_error;                /* set when a fetch failed on the link */
} frame;

static int stopped_locked(const c5_emu *e) { return e->abandon || e->gone; }

/* Reads [addr, addr + len) of host memory with dma_reads of at most C5_TLP_MAX_READ bytes,
 * C5_TLP_READ_WINDOW in flight. 0, or -1 with f->dma_error set (or the frame abandoned). */
static int dma_read(frame *f, uint64_t addr, uint32_t len, uint8_t *dst)
{
    c5_emu *e = f->e;
    pthread_mutex_lock(&e->mu);
    e->dma_error = NULL;
    uint32_t off = 0;
    for (;;) {
        while (off < len && e->reads_outstanding < C5_TLP_READ_WINDOW && !stopped_locked(e)) {
            while (e->rd[e->next_tag].active)
                e->next_tag++;
            uint8_t tag = e->next_tag++;
            uint32_t n = len - off < C5_TLP_MAX_READ ? len - off : C5_TLP_MAX_READ;
            e->rd[tag] = (c5_emu_read){1, addr + off, n, 0, dst + off};
            e->reads_outstanding++;
            c5_emu_send_locked(e, C5_TLP_DMA_READ, tag, C5_TLP_SC, n, addr + off, NULL);
            off += n;
        }
        if (e->dma_error || stopped_locked(e) || (off == len && e->reads_outstanding == 0))
            break;
        c5_emu_unlock(e); /* let the transport see the requests before we sleep */
        pthread_mutex_lock(&e->mu);
        if (!e->dma_error && !stopped_locked(e) && e->reads_outstanding > 0)
            pthread_cond_wait(&e->cv, &e->mu);
    }
    int rc = e->dma_error || stopped_locked(e) ? -1 : 0;
    f->dma_error = e->dma_error;
    for (int t = 0; t < 256; t++) /* late completions must not write into dst */
        e->rd[t].active = 0;
    e->reads_outstanding = 0;
    c5_emu_unlock(e);
    return rc;
}

static uint64_t reg_addr(const uint32_t *regs, uint32_t lo_off, uint32_t hi_off)
{
    return (uint64_t)regs[hi_off / 4] << 32 | regs[lo_off / 4];
}

static double reg_f64(const uint32_t *regs, uint32_t lo_off)
{
    uint64_t bits = reg_addr(regs, lo_off, lo_off + 4);
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

static size_t pad4(size_t n) { return (n + 3) & ~(size_t)3; }

/* c5_board_host.fetch: the DSP asks the host for a cell (fetch_request, dma_cell), waits for
 * the doorbell and reads the cell's buffer. */
static int host_fetch(void *ctx, int cell, uint8_t *dst, size_t bytes, c5_err *err)
{
    frame *f = ctx;
    c5_emu *e = f->e;
    pthread_mutex_lock(&e->mu);
    e->doorbell = 0;
    e->regs[C5_REG_DMA_CELL_OFFSET / 4] = c5_reg_dma_cell_set_cell(0, (uint32_t)cell);
    c5_emu_raise_locked(e, C5_REG_INT_STATUS_FETCH_REQUEST_MASK);
    c5_emu_unlock(e);
    pthread_mutex_lock(&e->mu);
    while (!e->doorbell && !stopped_locked(e))
        pthread_cond_wait(&e->cv, &e->mu);
    int stop = stopped_locked(e);
    uint64_t addr = e->db_addr;
    uint32_t len = e->db_len, dcell = e->db_cell;
    e->doorbell = 0;
    pthread_mutex_unlock(&e->mu);
    if (stop)
        return c5_fail(err, "frame abandoned");
    if (dcell != (uint32_t)cell || len != pad4(bytes)) {
        f->dma_error = "the DMA descriptor does not describe the cell asked for (cell or length)";
        return c5_fail(err, "%s", f->dma_error);
    }
    uint8_t *buf = malloc(len);
    if (!buf)
        return c5_fail(err, "out of memory for a cell");
    int rc = dma_read(f, addr, len, buf);
    if (rc == 0)
        memcpy(dst, buf, bytes);
    free(buf);
    return rc == 0 ? 0 : c5_fail(err, "cell %d: %s", cell, f->dma_error ? f->dma_error : "frame abandoned");
}

static void on_frame(void *ctx, const uint64_t *fb, int w, int h)
{
    frame *f = ctx;
    size_t n = (size_t)w * (size_t)h * 3;
    f->fb = malloc(n * sizeof *f->fb);
    if (!f->fb)
        return;
    for (size_t i = 0; i < n; i++)
        f->fb[i] = fb[i] > UINT32_MAX ? UINT32_MAX : (uint32_t)fb[i]; /* the model clamps the same way */
    f->w = w;
    f->h = h;
}

/* Checks the descriptor's header against its length and the registers; fills the scene's
 * grid shell and points at the flags. 0, or -1 with a message (status.error 1). */
static int read_descriptor(const frame *f, const uint8_t *d, uint32_t len, c5_scene *s, c5_supervol *sv,
                           const uint8_t **cell_flags, const uint8_t **block_flags, c5_err *err)
{
    c5_scene_descriptor_t h;
    if (len < C5_SCENE_DESCRIPTOR_BYTES)
        return c5_fail(err, "scene descriptor of %u bytes, its header alone is %d", len, C5_SCENE_DESCRIPTOR_BYTES);
    c5_scene_descriptor_unpack(d, &h);
    if (h.magic != 0x44533543u || h.version != 1 || h.header_bytes != C5_SCENE_DESCRIPTOR_BYTES)
        return c5_fail(err, "not a version-1 scene descriptor (magic 0x%08x, version %u, header %u bytes)",
                       (unsigned)h.magic, (unsigned)h.version, (unsigned)h.header_bytes);
    unsigned dims[3] = {h.dims_x, h.dims_y, h.dims_z};
    unsigned cells[3] = {h.cells_x, h.cells_y, h.cells_z};
    uint32_t split = f->regs[C5_REG_CELL_SPLIT_OFFSET / 4];
    unsigned want[3] = {c5_reg_cell_split_get_x(split), c5_reg_cell_split_get_y(split), c5_reg_cell_split_get_z(split)};
    int has_vol = dims[0] && dims[1] && dims[2];
    size_t ncells = 1;
    for (int a = 0; a < 3; a++) {
        want[a] = want[a] ? want[a] : 1;
        if (dims[a] > 512)
            return c5_fail(err, "grid of %ux%ux%u voxels: the board addresses 512 per axis", dims[0], dims[1], dims[2]);
        if (cells[a] != want[a])
            return c5_fail(err, "the descriptor's flags are for a %ux%ux%u split, cell_split says %ux%ux%u", cells[0],
                           cells[1], cells[2], want[0], want[1], want[2]);
        ncells *= cells[a];
    }
    size_t nblocks = 1;
    for (int a = 0; a < 3; a++)
        nblocks *= (dims[a] + 7) / 8;
    size_t want_cf = has_vol ? ncells : 0, want_bf = has_vol ? nblocks : 0;
    size_t o_json = C5_SCENE_DESCRIPTOR_BYTES, o_cf = o_json + pad4(h.json_bytes), o_bf = o_cf + pad4(h.cell_flags_bytes);
    if (h.cell_flags_bytes != want_cf || h.block_flags_bytes != want_bf ||
        o_bf + pad4(h.block_flags_bytes) != len || h.json_bytes > len)
        return c5_fail(err, "scene descriptor lengths do not add up (json %u, cell flags %u of %zu, block flags %u of %zu, "
                       "total %u)", (unsigned)h.json_bytes, (unsigned)h.cell_flags_bytes, want_cf,
                       (unsigned)h.block_flags_bytes, want_bf, len);
    char *json = malloc((size_t)h.json_bytes + 1);
    if (!json)
        return c5_fail(err, "out of memory for the scene");
    memcpy(json, d + o_json, h.json_bytes);
    json[h.json_bytes] = 0;
    int rc = c5_scene_parse(json, NULL, "scene descriptor", s, err);
    free(json);
    if (rc != 0)
        return -1;
    memset(sv, 0, sizeof *sv);
    uint32_t lohi[12] = {h.spacing_x_lo, h.spacing_x_hi, h.spacing_y_lo, h.spacing_y_hi, h.spacing_z_lo, h.spacing_z_hi,
                         h.origin_x_lo,  h.origin_x_hi,  h.origin_y_lo,  h.origin_y_hi,  h.origin_z_lo,  h.origin_z_hi};
    double g[6];
    for (int i = 0; i < 6; i++) {
        uint64_t bits = (uint64_t)lohi[2 * i + 1] << 32 | lohi[2 * i];
        memcpy(&g[i], &bits, sizeof g[i]);
    }
    sv->spacing = v3(g[0], g[1], g[2]);
    sv->origin = v3(g[3], g[4], g[5]);
    if (has_vol) {
        if (!(g[0] > 0 && g[1] > 0 && g[2] > 0))
            return c5_fail(err, "grid spacing (%g, %g, %g) is not positive", g[0], g[1], g[2]);
        for (int a = 0; a < 3; a++)
            sv->dims[a] = dims[a];
    }
    *cell_flags = d + o_cf;
    *block_flags = d + o_bf;
    return 0;
}

/* Renders one frame; returns the status.error code (0: done). */
static unsigned run_frame(frame *f, c5_board_stats *st)
{
    c5_err err = {0};
    uint32_t dlen = f->regs[C5_REG_SCENE_LENGTH_OFFSET / 4];
    uint64_t daddr = reg_addr(f->regs, C5_REG_SCENE_ADDR_LO_OFFSET, C5_REG_SCENE_ADDR_HI_OFFSET);
    if (dlen % 4 || dlen < C5_SCENE_DESCRIPTOR_BYTES)
        return ERR_SCENE;
    uint8_t *d = malloc(dlen);
    if (!d)
        return ERR_SCENE;
    unsigned code = 0;
    c5_scene *s = malloc(sizeof *s);
    c5_supervol sv;
    const uint8_t *cf = NULL, *bf = NULL;
    if (!s || dma_read(f, daddr, dlen, d) != 0) {
        code = ERR_DMA;
    } else if (read_descriptor(f, d, dlen, s, &sv, &cf, &bf, &err) != 0) {
        code = ERR_SCENE;
    } else {
        uint32_t size = f->regs[C5_REG_IMAGE_SIZE_OFFSET / 4], split = f->regs[C5_REG_CELL_SPLIT_OFFSET / 4];
        s->render.width = (int)c5_reg_image_size_get_width(size);
        s->render.height = (int)c5_reg_image_size_get_height(size);
        c5_camera cam = {
            .eye = v3(reg_f64(f->regs, C5_REG_CAM_EYE_X_LO_OFFSET), reg_f64(f->regs, C5_REG_CAM_EYE_Y_LO_OFFSET),
                      reg_f64(f->regs, C5_REG_CAM_EYE_Z_LO_OFFSET)),
            .target = v3(reg_f64(f->regs, C5_REG_CAM_TARGET_X_LO_OFFSET), reg_f64(f->regs, C5_REG_CAM_TARGET_Y_LO_OFFSET),
                         reg_f64(f->regs, C5_REG_CAM_TARGET_Z_LO_OFFSET)),
            .up = v3(reg_f64(f->regs, C5_REG_CAM_UP_X_LO_OFFSET), reg_f64(f->regs, C5_REG_CAM_UP_Y_LO_OFFSET),
                     reg_f64(f->regs, C5_REG_CAM_UP_Z_LO_OFFSET)),
            .fov_deg = reg_f64(f->regs, C5_REG_CAM_FOV_LO_OFFSET),
        };
        c5_board_host host = {f, host_fetch, cf, bf};
        c5_taps taps = {.ctx = f, .frame = on_frame};
        c5_board_opts o = {.cells = {(int)c5_reg_cell_split_get_x(split), (int)c5_reg_cell_split_get_y(split),
                                     (int)c5_reg_cell_split_get_z(split)},
                           .host = &host, .camera = &cam, .taps = &taps};
        c5_image img = {0};
        if (s->render.width < 1 || s->render.width > 512 || s->render.height < 1 || s->render.height > 512 ||
            !(cam.fov_deg > 0 && cam.fov_deg < 180))
            code = ERR_SCENE;
        else if (c5_board_render(s, &sv, 0, &o, &img, st, &err) != 0)
            code = f->dma_error ? ERR_DMA : ERR_SCENE;
        else if (!f->fb)
            code = ERR_SCENE; /* out of memory for the frame buffer copy */
        c5_image_free(&img);
    }
    free(s);
    free(d);
    return code;
}

/* Writes the frame buffer to fb_addr with dma_writes of C5_TLP_MAX_PAYLOAD bytes. */
static void write_frame_buffer(frame *f)
{
    c5_emu *e = f->e;
    uint64_t addr = reg_addr(f->regs, C5_REG_FB_ADDR_LO_OFFSET, C5_REG_FB_ADDR_HI_OFFSET);
    size_t bytes = (size_t)f->w * (size_t)f->h * 12;
    uint8_t *le = malloc(C5_TLP_MAX_PAYLOAD);
    if (!le)
        return;
    for (size_t off = 0; off < bytes; off += C5_TLP_MAX_PAYLOAD) {
        size_t n = bytes - off < C5_TLP_MAX_PAYLOAD ? bytes - off : C5_TLP_MAX_PAYLOAD;
        for (size_t i = 0; i < n / 4; i++) {
            uint32_t v = f->fb[off / 4 + i];
            le[4 * i] = (uint8_t)v;
            le[4 * i + 1] = (uint8_t)(v >> 8);
            le[4 * i + 2] = (uint8_t)(v >> 16);
            le[4 * i + 3] = (uint8_t)(v >> 24);
        }
        pthread_mutex_lock(&e->mu);
        if (f->gen == e->generation && !stopped_locked(e))
            c5_emu_send_locked(e, C5_TLP_DMA_WRITE, 0, C5_TLP_SC, (uint32_t)n, addr + off, le);
        c5_emu_unlock(e);
    }
    free(le);
}

static uint32_t sat32(uint64_t v) { return v > UINT32_MAX ? UINT32_MAX : (uint32_t)v; }

static void *frame_main(void *arg)
{
    frame *f = arg;
    c5_emu *e = f->e;
    c5_board_stats st;
    memset(&st, 0, sizeof st);
    unsigned code = run_frame(f, &st);
    if (code == 0)
        write_frame_buffer(f);
    pthread_mutex_lock(&e->mu);
    if (f->gen == e->generation && !stopped_locked(e)) {
        uint32_t *r = e->regs;
        uint32_t status = 0;
        if (code == 0) {
            uint64_t rays = 0;
            for (int i = 0; i < C5_RAY_TYPES; i++)
                rays += st.rays[i];
            r[C5_REG_CNT_FETCHES_OFFSET / 4] = sat32(st.fetches);
            r[C5_REG_CNT_RAYS_OFFSET / 4] = sat32(rays);
            r[C5_REG_CNT_BUS_PACKETS_OFFSET / 4] = sat32(st.bus_packets);
            r[C5_REG_CNT_SPILLS_OFFSET / 4] = sat32(st.spills);
            e->cycles = st.cycles;
            e->samples = st.samples;
            e->last = st;
            e->have_last = 1;
            status = c5_reg_status_set_frame_done(0, 1);
        } else {
            status = c5_reg_status_set_error(0, code);
        }
        r[C5_REG_STATUS_OFFSET / 4] = status; /* busy falls */
        c5_emu_raise_locked(e, code ? C5_REG_INT_STATUS_ERROR_MASK : C5_REG_INT_STATUS_FRAME_DONE_MASK);
    }
    e->thread_done = 1;
    pthread_cond_broadcast(&e->cv);
    c5_emu_unlock(e);
    free(f->fb);
    free(f);
    return NULL;
}

/* Waits (the lock released meanwhile) for a previous frame thread to finish, and joins it. */
static void reap_locked(c5_emu *e)
{
    if (!e->thread_live)
        return;
    while (!e->thread_done)
        pthread_cond_wait(&e->cv, &e->mu);
    pthread_join(e->thread, NULL); /* it has released the lock and is returning */
    e->thread_live = 0;
}

void c5_emu_start_locked(c5_emu *e)
{
    if (c5_reg_status_get_busy(e->regs[C5_REG_STATUS_OFFSET / 4]))
        return; /* ignored while busy (register map) */
    reap_locked(e);
    frame *f = calloc(1, sizeof *f);
    if (!f) {
        e->regs[C5_REG_STATUS_OFFSET / 4] = c5_reg_status_set_error(0, ERR_SCENE);
        c5_emu_raise_locked(e, C5_REG_INT_STATUS_ERROR_MASK);
        return;
    }
    e->abandon = 0;
    e->generation++;
    f->e = e;
    f->gen = e->generation;
    memcpy(f->regs, e->regs, sizeof f->regs);
    e->regs[C5_REG_STATUS_OFFSET / 4] = c5_reg_status_set_busy(0, 1);
    for (uint32_t off = C5_REG_CNT_FETCHES_OFFSET; off <= C5_REG_CNT_SPILLS_OFFSET; off += 4)
        e->regs[off / 4] = 0;
    e->cycles = e->samples = 0;
    e->thread_done = 0;
    if (pthread_create(&e->thread, NULL, frame_main, f) != 0) {
        free(f);
        e->thread_done = 1;
        e->regs[C5_REG_STATUS_OFFSET / 4] = c5_reg_status_set_error(0, ERR_SCENE);
        c5_emu_raise_locked(e, C5_REG_INT_STATUS_ERROR_MASK);
        return;
    }
    e->thread_live = 1;
}

void c5_emu_abandon_locked(c5_emu *e)
{
    e->abandon = 1;
    pthread_cond_broadcast(&e->cv);
}

void c5_emu_join(c5_emu *e)
{
    pthread_mutex_lock(&e->mu);
    reap_locked(e);
    pthread_mutex_unlock(&e->mu);
}
