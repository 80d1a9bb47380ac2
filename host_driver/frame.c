/* A frame (docs/host-protocol.md, "A frame"): load the scene into host memory, program the
 * registers and start, serve fetch requests until frame_done, read the result. */
#include <stdlib.h>
#include <string.h>

#include "c5_regs_map.h"
#include "core.h"
#include "ray.h"

int c5drv_load_scene(c5drv *d, const char *json, const char *base_dir, const char *what, const int cells[3],
                     int width, int height)
{
    int rc = drv_begin(d);
    if (rc)
        return rc;
    if (!json || width < 0 || height < 0)
        return drv_fail(d, C5DRV_E_ARG, "c5drv_load_scene: no JSON text, or a negative image size");
    if (d->state == DRV_RUNNING)
        return drv_fail(d, C5DRV_E_STATE, "a frame is running: wait for it or reset the board first");
    for (int a = 0; cells && a < 3; a++)
        if (cells[a] < 0 || cells[a] > 255) /* cell_split holds 8 bits per axis */
            return drv_fail(d, C5DRV_E_ARG, "%d cells along %c: the board's cell_split holds 0..255", cells[a],
                            "xyz"[a]);
    if (d->loaded) {
        c5_hostmem_free(&d->hm);
        d->loaded = 0;
    }
    d->state = DRV_IDLE;
    c5_err err;
    if (c5_hostmem_load(&d->hm, json, base_dir, what, cells, width, height, &err) != 0)
        return drv_fail(d, strstr(err.msg, "out of memory") ? C5DRV_E_NOMEM : C5DRV_E_SCENE, "%s", err.msg);
    d->loaded = 1;
    return C5DRV_OK;
}

static void split_double(double v, uint32_t w[2])
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    w[0] = (uint32_t)bits;
    w[1] = (uint32_t)(bits >> 32);
}

typedef struct {
    uint32_t off, val;
} reg_word;

/* Register writes of a frame, in the protocol's order, up to (not including) control. */
static int program(c5drv *d, int frame)
{
    const c5_hostmem *m = &d->hm;
    c5_camera cam = c5_scene_camera_at(m->scene, frame);
    double cv[10] = {cam.eye.x,    cam.eye.y,    cam.eye.z,    cam.target.x, cam.target.y,
                     cam.target.z, cam.up.x,     cam.up.y,     cam.up.z,     cam.fov_deg};
    reg_word w[40];
    int n = 0;
    w[n++] = (reg_word){C5_REG_IMAGE_SIZE_OFFSET,
                            c5_reg_image_size_set_height(c5_reg_image_size_set_width(0, (uint32_t)m->width),
                                                         (uint32_t)m->height)};
    w[n++] = (reg_word){C5_REG_CELL_SPLIT_OFFSET,
                            c5_reg_cell_split_set_z(c5_reg_cell_split_set_y(c5_reg_cell_split_set_x(0, (uint32_t)m->cells[0]),
                                                                             (uint32_t)m->cells[1]),
                                                    (uint32_t)m->cells[2])};
    /* cam_eye_x_lo .. cam_fov_hi are consecutive lo/hi pairs in cv's order */
    for (int i = 0; i < 10; i++) {
        uint32_t p[2];
        split_double(cv[i], p);
        w[n++] = (reg_word){C5_REG_CAM_EYE_X_LO_OFFSET + 8u * (uint32_t)i, p[0]};
        w[n++] = (reg_word){C5_REG_CAM_EYE_X_HI_OFFSET + 8u * (uint32_t)i, p[1]};
    }
    w[n++] = (reg_word){C5_REG_SCENE_ADDR_LO_OFFSET, (uint32_t)m->desc.addr};
    w[n++] = (reg_word){C5_REG_SCENE_ADDR_HI_OFFSET, (uint32_t)(m->desc.addr >> 32)};
    w[n++] = (reg_word){C5_REG_SCENE_LENGTH_OFFSET, (uint32_t)m->desc.len};
    w[n++] = (reg_word){C5_REG_FB_ADDR_LO_OFFSET, (uint32_t)m->fb.addr};
    w[n++] = (reg_word){C5_REG_FB_ADDR_HI_OFFSET, (uint32_t)(m->fb.addr >> 32)};
    w[n++] = (reg_word){C5_REG_INT_MASK_OFFSET, 0};
    w[n++] = (reg_word){C5_REG_INT_STATUS_OFFSET, C5_REG_INT_STATUS_ERROR_MASK |
                                                          C5_REG_INT_STATUS_FETCH_REQUEST_MASK |
                                                          C5_REG_INT_STATUS_FRAME_DONE_MASK};
    for (int i = 0; i < n; i++) {
        int rc = drv_reg_write(d, w[i].off, w[i].val, 0);
        if (rc)
            return rc;
    }
    return C5DRV_OK;
}

int c5drv_start_frame(c5drv *d, int frame)
{
    int rc = drv_begin(d);
    if (rc)
        return rc;
    if (!d->loaded)
        return drv_fail(d, C5DRV_E_STATE, "no scene loaded");
    if (d->state == DRV_RUNNING)
        return drv_fail(d, C5DRV_E_STATE, "a frame is running: wait for it or reset the board first");
    int frames = c5_scene_frames(d->hm.scene);
    if (frame < 0 || frame >= frames)
        return drv_fail(d, C5DRV_E_ARG, "frame %d: the scene has frames 0..%d", frame, frames - 1);
    memset(&d->cnt, 0, sizeof d->cnt);
    memset(d->hm.fb.data, 0, d->hm.fb.len);
    d->ur_seen = 0;
    d->up_active = 0;
    d->frame = frame;
    d->t_start = drv_now();
    if ((rc = program(d, frame)) != C5DRV_OK)
        return rc;
    /* Interrupts raised before the clear above (a stale bit unmasked) are not this frame's. */
    d->irq = 0;
    uint32_t ctl = c5_reg_control_set_start_frame(c5_reg_control_set_int_enable(0, 1), 1);
    if ((rc = drv_reg_write(d, C5_REG_CONTROL_OFFSET, ctl, 0)) != C5DRV_OK)
        return rc;
    d->state = DRV_RUNNING;
    return C5DRV_OK;
}

static const char *board_error_name(unsigned code)
{
    switch (code) {
    case 1: return "scene parameters out of range";
    case 2: return "Cell Tree overflow";
    case 3: return "DMA fault";
    default: return "reserved code";
    }
}

/* Acknowledges an interrupt source (int_status is write-one-to-clear) and reads the register
 * that says what it was about. */
static int ack_and_read(c5drv *d, uint32_t source, uint32_t off, uint32_t *v, double deadline)
{
    int rc = drv_reg_write(d, C5_REG_INT_STATUS_OFFSET, source, deadline);
    return rc ? rc : drv_reg_read(d, off, v, deadline);
}

/* fetch_request: acknowledge, learn the cell, describe its buffer and ring the doorbell. */
static int serve_fetch(c5drv *d, double deadline)
{
    uint32_t v = 0;
    int rc = ack_and_read(d, C5_REG_INT_STATUS_FETCH_REQUEST_MASK, C5_REG_DMA_CELL_OFFSET, &v, deadline);
    if (rc)
        return rc;
    unsigned cell = c5_reg_dma_cell_get_cell(v);
    const c5_hostmem *m = &d->hm;
    if (!m->has_volume || cell >= (unsigned)m->ncells)
        return drv_fail(d, C5DRV_E_PROTOCOL, "the board asked for cell %u; the scene has %d", cell,
                        m->has_volume ? m->ncells : 0);
    const c5_hm_buf *b = &m->cell[cell];
    if ((rc = drv_reg_write(d, C5_REG_DMA_ADDR_LO_OFFSET, (uint32_t)b->addr, deadline)) ||
        (rc = drv_reg_write(d, C5_REG_DMA_ADDR_HI_OFFSET, (uint32_t)(b->addr >> 32), deadline)) ||
        (rc = drv_reg_write(d, C5_REG_DMA_LENGTH_OFFSET, (uint32_t)b->len, deadline)))
        return rc;
    /* armed before the doorbell: the board may read before the doorbell's completion arrives */
    d->up_active = 1;
    d->up_addr = b->addr;
    d->up_end = b->addr + b->len;
    d->up_left = b->len;
    d->up_t0 = drv_now();
    if ((rc = drv_reg_write(d, C5_REG_DMA_DOORBELL_OFFSET, c5_reg_dma_doorbell_set_ring(0, 1), deadline)))
        return rc;
    d->cnt.fetches_served++;
    return C5DRV_OK;
}

static int board_error(c5drv *d, double deadline)
{
    uint32_t st = 0;
    int rc = ack_and_read(d, C5_REG_INT_STATUS_ERROR_MASK, C5_REG_STATUS_OFFSET, &st, deadline);
    if (rc)
        return rc;
    unsigned code = c5_reg_status_get_error(st);
    if (d->ur_seen)
        return drv_fail(d, C5DRV_E_BOARD, "the board stopped the frame: status.error %u (%s; a dma_read at 0x%llx "
                        "was outside host memory)", code, board_error_name(code), (unsigned long long)d->ur_addr);
    return drv_fail(d, C5DRV_E_BOARD, "the board stopped the frame: status.error %u (%s)", code,
                    board_error_name(code));
}

static int read_board_counters(c5drv *d, c5drv_counters *c, double deadline)
{
    static const uint32_t offs[] = {C5_REG_CNT_FETCHES_OFFSET,    C5_REG_CNT_CYCLES_LO_OFFSET,
                                    C5_REG_CNT_CYCLES_HI_OFFSET,  C5_REG_CNT_SAMPLES_LO_OFFSET,
                                    C5_REG_CNT_SAMPLES_HI_OFFSET, C5_REG_CNT_RAYS_OFFSET,
                                    C5_REG_CNT_BUS_PACKETS_OFFSET, C5_REG_CNT_SPILLS_OFFSET};
    uint32_t v[8];
    /* in this order: reading _lo latches _hi */
    for (int i = 0; i < 8; i++) {
        int rc = drv_reg_read(d, offs[i], &v[i], deadline);
        if (rc)
            return rc;
    }
    c->fetches = v[0];
    c->cycles = (uint64_t)v[2] << 32 | v[1];
    c->samples = (uint64_t)v[4] << 32 | v[3];
    c->rays = v[5];
    c->bus_packets = v[6];
    c->spills = v[7];
    return C5DRV_OK;
}

static int frame_done(c5drv *d, double deadline)
{
    int rc = drv_reg_write(d, C5_REG_INT_STATUS_OFFSET, C5_REG_INT_STATUS_FRAME_DONE_MASK, deadline);
    if (rc || (rc = read_board_counters(d, &d->cnt, deadline)))
        return rc;
    if (d->cnt.fb_bytes < d->hm.fb.len)
        return drv_fail(d, C5DRV_E_PROTOCOL, "frame_done after %llu bytes of frame buffer; the frame has %zu",
                        (unsigned long long)d->cnt.fb_bytes, d->hm.fb.len);
    d->cnt.frame_s = drv_now() - d->t_start;
    return C5DRV_OK;
}

int c5drv_wait_frame(c5drv *d, unsigned timeout_ms)
{
    int rc = drv_begin(d);
    if (rc)
        return rc;
    if (d->state != DRV_RUNNING)
        return drv_fail(d, C5DRV_E_STATE, "no frame running: start one first");
    double deadline = drv_now() + timeout_ms * 1e-3;
    for (;;) {
        if (d->irq & C5_REG_INT_STATUS_ERROR_MASK) {
            d->irq = 0;
            rc = board_error(d, deadline);
            if (rc == C5DRV_OK) /* not reached: board_error always names the error */
                rc = C5DRV_E_BOARD;
            break;
        }
        if (d->irq & C5_REG_INT_STATUS_FETCH_REQUEST_MASK) {
            d->irq &= ~C5_REG_INT_STATUS_FETCH_REQUEST_MASK;
            if ((rc = serve_fetch(d, deadline)) != C5DRV_OK)
                break;
            continue;
        }
        if (d->irq & C5_REG_INT_STATUS_FRAME_DONE_MASK) {
            d->irq = 0;
            if ((rc = frame_done(d, deadline)) == C5DRV_OK) {
                d->state = DRV_DONE;
                return C5DRV_OK;
            }
            break;
        }
        double left = (deadline - drv_now()) * 1e3;
        if (left <= 0) {
            rc = drv_fail(d, C5DRV_E_TIMEOUT, "the frame did not complete within %u ms", timeout_ms);
            break;
        }
        unsigned ms = left < C5DRV_IO_TIMEOUT_MS ? (unsigned)left + 1 : C5DRV_IO_TIMEOUT_MS;
        rc = drv_pump(d, ms);
        if (rc != C5DRV_OK && rc != C5DRV_E_TIMEOUT) /* silence is fine until the deadline */
            break;
    }
    /* any failure ends the frame here; the board may still run: reset it before the next */
    d->state = DRV_IDLE;
    d->up_active = 0;
    return rc;
}

void c5drv_image_free(c5drv_image *img)
{
    if (!img)
        return;
    free(img->rgb);
    memset(img, 0, sizeof *img);
}

int c5drv_read_frame(c5drv *d, c5drv_image *out)
{
    if (out)
        memset(out, 0, sizeof *out);
    int rc = drv_begin(d);
    if (rc)
        return rc;
    if (!out)
        return drv_fail(d, C5DRV_E_ARG, "no image to read the frame into");
    if (d->state != DRV_DONE)
        return drv_fail(d, C5DRV_E_STATE, "no completed frame");
    /* the size was checked against the board's limit (512 x 512) when the scene was loaded */
    size_t n = (size_t)d->hm.width * (size_t)d->hm.height * 3;
    if (!(out->rgb = malloc(n * sizeof *out->rgb)))
        return drv_fail(d, C5DRV_E_NOMEM, "out of memory for a %dx%d frame", d->hm.width, d->hm.height);
    out->w = d->hm.width;
    out->h = d->hm.height;
    const uint8_t *p = d->hm.fb.data;
    for (size_t i = 0; i < n; i++, p += 4) {
        uint32_t word = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
        out->rgb[i] = c5_rgb_float(word); /* as c5_board_render: frame_acc UQ20.12 */
    }
    return C5DRV_OK;
}

const uint32_t *c5drv_frame_words(const c5drv *d, int *w, int *h)
{
    if (!d || d->state != DRV_DONE)
        return NULL;
    if (w)
        *w = d->hm.width;
    if (h)
        *h = d->hm.height;
    /* the buffer is malloc'd (aligned for uint32_t) and the link is little endian like the host */
    return (const uint32_t *)(const void *)d->hm.fb.data;
}

int c5drv_read_counters(c5drv *d, c5drv_counters *c)
{
    int rc = drv_begin(d);
    if (rc)
        return rc;
    if (d->state == DRV_RUNNING)
        return drv_fail(d, C5DRV_E_STATE, "a frame is running: the counters hold the previous frame's snapshot");
    *c = d->cnt; /* the driver's side of the last frame on this handle (zeros in a fresh one) */
    return read_board_counters(d, c, 0);
}
