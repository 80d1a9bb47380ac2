/* The host driver against the emulated board core in-process: a loopback c5drv_transport
 * whose send is c5_emu_out and whose recv is c5_emu_in_wait + c5_emu_in_pop, no USB. A frame
 * through the driver must be bit-identical to c5_board_render of the same scene, and every
 * injected link fault must give its error (docs/host-protocol.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "builtin_scenes.h"
#include "c5_regs_map.h"
#include "c5drv.h"
#include "emu_board.h"
#include "harness.h"
#include "supervol.h"
#include "tlp.h"

#define SIZE 32
#define FRAME_MS 60000u

/* A register write the loopback alters on its way to the board (tests of the board's own
 * errors): offset, and the value to add to what the driver wrote. */
static struct {
    int on;
    uint32_t off, add;
} tamper;

static int lb_send(void *ctx, const uint8_t *pkt, size_t len, unsigned ms, char *msg, size_t cap)
{
    (void)ms;
    uint8_t copy[C5_TLP_HEADER_BYTES + 4];
    c5_tlp_header_t h;
    c5_tlp_header_unpack(pkt, &h);
    if (tamper.on && h.type == C5_TLP_REG_WRITE && h.addr_lo == tamper.off && len == sizeof copy) {
        memcpy(copy, pkt, len);
        copy[C5_TLP_HEADER_BYTES] = (uint8_t)(copy[C5_TLP_HEADER_BYTES] + tamper.add);
        pkt = copy;
    }
    if (c5_emu_out(ctx, pkt, len) == C5_EMU_GONE) {
        snprintf(msg, cap, "loopback: the board is gone");
        return C5DRV_E_DISCONNECTED;
    }
    return C5DRV_OK;
}

static int lb_recv(void *ctx, uint8_t *buf, size_t cap, size_t *got, unsigned ms, char *msg, size_t mcap)
{
    *got = 0;
    if (!c5_emu_in_wait(ctx, ms)) {
        snprintf(msg, mcap, "loopback: nothing within %u ms", ms);
        return C5DRV_E_TIMEOUT;
    }
    switch (c5_emu_in_pop(ctx, buf, cap, got)) {
    case C5_EMU_PACKET: return C5DRV_OK;
    case C5_EMU_STALL: snprintf(msg, mcap, "loopback: IN stalled"); return C5DRV_E_STALL;
    case C5_EMU_GONE: snprintf(msg, mcap, "loopback: the board is gone"); return C5DRV_E_DISCONNECTED;
    default: snprintf(msg, mcap, "loopback: nothing pending"); return C5DRV_E_TIMEOUT;
    }
}

static int lb_clear_halt(void *ctx, int in, char *msg, size_t cap)
{
    (void)ctx, (void)in, (void)msg, (void)cap;
    return C5DRV_OK; /* the emulated board's stall lasts one IN transfer */
}

static const char *lb_serial(void *ctx) { return c5_emu_serial(ctx); }

static void lb_close(void *ctx) { (void)ctx; } /* the test frees the board after the driver */

static c5drv *open_loop(c5_emu *e)
{
    c5drv_transport t = {e, lb_send, lb_recv, lb_clear_halt, lb_close, lb_serial};
    c5drv *d = NULL;
    char msg[256];
    return c5drv_open(&t, &d, msg, sizeof msg) == C5DRV_OK ? d : NULL;
}

/* The model's own frame of the scene, as 'cube5 render' would make it. */
static int model_render(const char *json, const int cells[3], c5_image *img, c5_board_stats *st)
{
    c5_scene *s = calloc(1, sizeof *s);
    c5_supervol sv = {0};
    c5_err err;
    int rc = -1;
    if (s && c5_scene_parse(json, NULL, "test", s, &err) == 0) {
        s->render.width = s->render.height = SIZE;
        c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}};
        if (c5_supervol_build(s, &sv, &err) == 0)
            rc = c5_board_render(s, &sv, 0, &o, img, st, &err);
        if (rc)
            fprintf(stderr, "model: %s\n", err.msg);
        c5_supervol_free(&sv);
    }
    free(s);
    return rc;
}

/* One frame through the driver, compared bit for bit with the model. */
static void render_matches(const char *json, const int cells[3])
{
    c5_image want = {0};
    c5drv_image got = {0};
    c5_board_stats mst, est;
    CHECK(model_render(json, cells, &want, &mst) == 0);
    c5_emu *e = c5_emu_new(NULL);
    c5drv *d = open_loop(e);
    CHECK(d);
    c5drv_info info;
    int rc = c5drv_identify(d, &info);
    CHECK_MSG(rc == C5DRV_OK, "identify: %s", c5drv_message(d));
    CHECK(info.id == 0x43554235u && info.major == 1);
    CHECK(strcmp(info.serial, c5_emu_serial(e)) == 0);
    rc = c5drv_load_scene(d, json, NULL, "test", cells, SIZE, SIZE);
    CHECK_MSG(rc == C5DRV_OK, "load: %s", c5drv_message(d));
    rc = c5drv_start_frame(d, 0);
    CHECK_MSG(rc == C5DRV_OK, "start: %s", c5drv_message(d));
    rc = c5drv_wait_frame(d, FRAME_MS);
    CHECK_MSG(rc == C5DRV_OK, "wait: %d %s", rc, c5drv_message(d));
    rc = c5drv_read_frame(d, &got);
    CHECK_MSG(rc == C5DRV_OK, "read: %s", c5drv_message(d));
    c5drv_counters c;
    rc = c5drv_read_counters(d, &c);
    CHECK_MSG(rc == C5DRV_OK, "counters: %s", c5drv_message(d));
    CHECK(c5_emu_last_stats(e, &est) == 0);
    CHECK_INT(got.w, want.w);
    CHECK_INT(got.h, want.h);
    size_t n = (size_t)SIZE * SIZE * 3, diff = 0;
    for (size_t i = 0; i < n; i++)
        diff += memcmp(&got.rgb[i], &want.rgb[i], sizeof(float)) != 0;
    CHECK_MSG(diff == 0, "%zu of %zu channels differ from c5_board_render", diff, n);
    int w, h;
    const uint32_t *words = c5drv_frame_words(d, &w, &h);
    CHECK(words && w == SIZE && h == SIZE);
    CHECK_INT(c.fetches_served, mst.fetches);
    CHECK_INT(c.fetches_served, est.fetches);
    CHECK_INT(c.fetches, mst.fetches);
    CHECK_INT(c.samples, mst.samples);
    CHECK_INT(c.cycles, mst.cycles);
    CHECK_INT(c.bus_packets, mst.bus_packets);
    CHECK_INT(c.fb_bytes, (uint64_t)SIZE * SIZE * 12);
    CHECK_INT(c.stall_retries, 0);
    CHECK(mst.fetches == 0 || (c.cell_bytes > 0 && c.cell_upload_s > 0));
    CHECK(c.frame_s > 0);
    c5drv_close(d);
    c5_emu_free(e);
    c5_image_free(&want);
    c5drv_image_free(&got);
}

TEST(driver_default_1cell_matches_model)
{
    int cells[3] = {1, 1, 1};
    render_matches(c5_builtin_scene_json("default"), cells);
}

TEST(driver_default_2x2x2_matches_model)
{
    int cells[3] = {2, 2, 2};
    render_matches(c5_builtin_scene_json("default"), cells);
}

/* No volume: no cell buffers, no fetches, the descriptor with dims 0 and cells 1,1,1. The
 * split asked for is forced to 1x1x1, as c5_board_render does. */
TEST(driver_surfaces_only_matches_model)
{
    static const char json[] =
        "{\"surfaces\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 10,"
        " \"material\": {\"color\": [0.8, 0.3, 0.2]}}],"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.4, 0.3, -1], \"intensity\": 1.0}],"
        " \"camera\": {\"eye\": [0, -60, 20], \"target\": [0, 0, 0], \"up\": [0, 0, 1], \"fov\": 34}}";
    int cells[3] = {2, 2, 2};
    render_matches(json, cells);
}

TEST(driver_bad_scene_is_refused)
{
    c5_emu *e = c5_emu_new(NULL);
    c5drv *d = open_loop(e);
    CHECK(d);
    int rc = c5drv_load_scene(d, "{\"camera\": {\"fov\": 190}}", NULL, "bad", NULL, 0, 0);
    CHECK_INT(rc, C5DRV_E_SCENE);
    CHECK_HAS(c5drv_message(d), "camera");
    int cells[3] = {100, 1, 1}; /* more than the packet's 64 cells: the model refuses */
    rc = c5drv_load_scene(d, c5_builtin_scene_json("default"), NULL, "default", cells, SIZE, SIZE);
    CHECK_INT(rc, C5DRV_E_SCENE);
    rc = c5drv_load_scene(d, c5_builtin_scene_json("default"), NULL, "default", NULL, 1024, 16);
    CHECK_INT(rc, C5DRV_E_SCENE);
    CHECK_INT(c5drv_start_frame(d, 0), C5DRV_E_STATE); /* nothing loaded */
    c5drv_close(d);
    c5_emu_free(e);
}

TEST(driver_calls_out_of_order)
{
    c5_emu *e = c5_emu_new(NULL);
    c5drv *d = open_loop(e);
    CHECK(d);
    CHECK_INT(c5drv_wait_frame(d, 100), C5DRV_E_STATE);
    c5drv_image img = {0};
    CHECK_INT(c5drv_read_frame(d, &img), C5DRV_E_STATE);
    CHECK(img.rgb == NULL && img.w == 0 && img.h == 0);
    CHECK_INT(c5drv_read_frame(d, NULL), C5DRV_E_ARG);
    c5drv_image_free(&img); /* a zeroed image and NULL: nothing to free */
    c5drv_image_free(NULL);
    CHECK(c5drv_frame_words(d, NULL, NULL) == NULL);
    uint32_t v;
    CHECK_INT(c5drv_reg_read(d, 3, &v), C5DRV_E_ARG);     /* unaligned */
    CHECK_INT(c5drv_reg_read(d, 0x200, &v), C5DRV_E_ARG); /* beyond BAR0 */
    CHECK_INT(c5drv_reg_read(d, C5_REG_ID_OFFSET, &v), C5DRV_OK);
    CHECK_INT(v, 0x43554235u);
    CHECK_INT(c5drv_reset(d), C5DRV_OK);
    c5drv_close(d);
    c5_emu_free(e);
}

/* A board, the driver on it over the loopback, and `default` loaded at 16x16 in 2 cells:
 * the load's result, or 1 when no handle could be opened (*d NULL). */
static int loop_with_default(c5_emu **e, c5drv **d)
{
    *e = c5_emu_new(NULL);
    *d = open_loop(*e);
    if (!*d) {
        c5_emu_free(*e);
        return 1;
    }
    int cells[3] = {2, 1, 1};
    return c5drv_load_scene(*d, c5_builtin_scene_json("default"), NULL, "default", cells, 16, 16);
}

/* A frame with one link fault armed: the driver's error, and nothing hangs or leaks. After
 * a failure, the next call on the handle must fail as cleanly (disconnect: at once). */
static int faulty_frame(const c5_fault *f, c5drv_counters *c, int *after, char *msg, size_t cap)
{
    c5_emu *e;
    c5drv *d;
    int rc = loop_with_default(&e, &d);
    if (!d)
        return 1;
    c5_emu_set_fault(e, f);
    if (rc == C5DRV_OK)
        rc = c5drv_start_frame(d, 0);
    if (rc == C5DRV_OK)
        rc = c5drv_wait_frame(d, 5000);
    snprintf(msg, cap, "%s", c5drv_message(d));
    if (rc == C5DRV_OK && c)
        rc = c5drv_read_counters(d, c);
    if (after) {
        uint32_t v;
        *after = c5drv_reg_read(d, C5_REG_ID_OFFSET, &v);
    }
    c5drv_close(d);
    c5_emu_free(e);
    return rc;
}

TEST(driver_stall_recovers)
{
    c5_fault f = {C5_FAULT_STALL, 0, 3, 2};
    c5drv_counters c;
    char msg[512];
    int rc = faulty_frame(&f, &c, NULL, msg, sizeof msg);
    CHECK_MSG(rc == C5DRV_OK, "%d %s", rc, msg);
    CHECK_INT(c.stall_retries, 2);
}

/* Each fault that ends the frame: its error and a word of its message. */
TEST(driver_faults_give_their_errors)
{
    static const struct {
        c5_fault f;
        int code;
        const char *word;
    } cases[] = {
        {{C5_FAULT_STALL, C5_TLP_INTERRUPT, 1, C5DRV_STALL_RETRIES + 1}, C5DRV_E_STALL, "stalled"},
        {{C5_FAULT_SHORT, C5_TLP_DMA_READ, 2, 0}, C5DRV_E_SHORT, "short"},
        {{C5_FAULT_CORRUPT, C5_TLP_REG_COMPLETION, 4, 0}, C5DRV_E_PROTOCOL, "sync"},
        {{C5_FAULT_TIMEOUT, C5_TLP_INTERRUPT, 1, 0}, C5DRV_E_TIMEOUT, "within"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char msg[512];
        int rc = faulty_frame(&cases[i].f, NULL, NULL, msg, sizeof msg);
        CHECK_MSG(rc == cases[i].code, "case %zu: %s expected, got %s: %s", i, c5drv_strerror(cases[i].code),
                  c5drv_strerror(rc), msg);
        CHECK_HAS(msg, cases[i].word);
    }
}

TEST(driver_disconnect)
{
    c5_fault f = {C5_FAULT_DISCONNECT, C5_TLP_DMA_READ, 3, 0};
    char msg[512];
    int after = 0;
    CHECK_INT(faulty_frame(&f, NULL, &after, msg, sizeof msg), C5DRV_E_DISCONNECTED);
    CHECK_INT(after, C5DRV_E_DISCONNECTED);
}

/* The board's own errors reach the caller as C5DRV_E_BOARD with the code named. */
static int tampered_frame(uint32_t off, uint32_t add, char *msg, size_t cap)
{
    c5_emu *e;
    c5drv *d;
    int rc = loop_with_default(&e, &d);
    if (!d)
        return 1;
    tamper.on = 1;
    tamper.off = off;
    tamper.add = add;
    if (rc == C5DRV_OK)
        rc = c5drv_start_frame(d, 0);
    if (rc == C5DRV_OK)
        rc = c5drv_wait_frame(d, FRAME_MS);
    tamper.on = 0;
    snprintf(msg, cap, "%s", c5drv_message(d));
    c5drv_close(d);
    c5_emu_free(e);
    return rc;
}

TEST(driver_board_scene_error)
{
    char msg[512];
    /* cell_split 3x1x1 against a descriptor for 2x1x1 */
    CHECK_INT(tampered_frame(C5_REG_CELL_SPLIT_OFFSET, 1, msg, sizeof msg), C5DRV_E_BOARD);
    CHECK_HAS(msg, "status.error 1 (scene parameters out of range)");
}

TEST(driver_board_dma_fault)
{
    char msg[512];
    /* a descriptor 4 bytes longer than the cell: the board refuses it */
    CHECK_INT(tampered_frame(C5_REG_DMA_LENGTH_OFFSET, 4, msg, sizeof msg), C5DRV_E_BOARD);
    CHECK_HAS(msg, "status.error 3 (DMA fault)");
}

TEST(driver_dma_read_outside_host_memory)
{
    char msg[512];
    /* the cell's address moved to 0x13_0000_0000, where no buffer is: the reads get UR */
    CHECK_INT(tampered_frame(C5_REG_DMA_ADDR_HI_OFFSET, 0x10, msg, sizeof msg), C5DRV_E_BOARD);
    CHECK_HAS(msg, "status.error 3 (DMA fault");
    CHECK_HAS(msg, "outside host memory");
}
