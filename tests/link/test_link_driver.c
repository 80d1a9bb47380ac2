/* The host driver over real libusb against the emulated board on umockdev: a frame
 * through the driver is bit-identical to the model rendering directly and the driver served
 * exactly the model's cell fetches; every injected link fault gives its documented error
 * (docs/host-protocol.md, "What the driver does when the link misbehaves"). */
#include <string.h>
#include <time.h>

#include "board.h"
#include "builtin_scenes.h"
#include "c5drv.h"
#include "harness.h"
#include "supervol.h"
#include "tlp.h"
#include "usb_fixture.h"
#include "clock.h"

typedef struct {
    c5_link_fixture fx;
    c5drv *d;
    char msg[512];
} link;

/* A board on the emulated bus and the driver opened on it by VID:PID and serial. */
static int up(link *l, const char *serial)
{
    memset(l, 0, sizeof *l);
    if (c5_link_fixture_up(&l->fx, serial) != 0) {
        snprintf(l->msg, sizeof l->msg, "%s", l->fx.msg);
        return -1;
    }
    return c5drv_open_usb(C5_USB_VID, C5_USB_PID, serial, &l->d, l->msg, sizeof l->msg);
}

static void down(link *l)
{
    c5drv_close(l->d);
    c5_link_fixture_down(&l->fx);
}

/* The model rendering the scene directly: frame `frame` at w x h with the split. */
static int model_render(const char *name, int w, int h, int cells, int frame, c5_image *img, c5_board_stats *st)
{
    c5_scene s;
    c5_supervol sv;
    c5_err err = {0};
    if (c5_scene_parse(c5_builtin_scene_json(name), NULL, name, &s, &err) != 0)
        return -1;
    s.render.width = w;
    s.render.height = h;
    if (c5_supervol_build(&s, &sv, &err) != 0)
        return -1;
    c5_board_opts o = {.cells = {cells, cells, cells}};
    int rc = c5_board_render(&s, &sv, frame, &o, img, st, &err);
    c5_supervol_free(&sv);
    return rc;
}

static int drv_render(link *l, const char *name, int w, int h, int cells, int frame, unsigned timeout_ms)
{
    int split[3] = {cells, cells, cells};
    int rc = c5drv_load_scene(l->d, c5_builtin_scene_json(name), NULL, name, split, w, h);
    if (rc == C5DRV_OK)
        rc = c5drv_start_frame(l->d, frame);
    if (rc == C5DRV_OK)
        rc = c5drv_wait_frame(l->d, timeout_ms);
    return rc;
}

/* One scene through the driver and directly: same bits, same fetches. */
static void same_frame(const char *name, int w, int h, int cells, int frame)
{
    link l;
    CHECK_MSG(up(&l, NULL) == C5DRV_OK, "%s", l.msg);
    c5drv_image via = {0};
    c5_image direct = {0};
    c5_board_stats st;
    int rc = drv_render(&l, name, w, h, cells, frame, 120000);
    if (rc != C5DRV_OK) {
        c5t_failf(__FILE__, __LINE__, "%s: %s: %s", name, c5drv_strerror(rc), c5drv_message(l.d));
        down(&l);
        return;
    }
    c5drv_counters c;
    c5_board_stats board_st;
    int ok = c5drv_read_frame(l.d, &via) == C5DRV_OK && c5drv_read_counters(l.d, &c) == C5DRV_OK &&
             c5_emu_last_stats(l.fx.board, &board_st) == 0;
    down(&l);
    CHECK_MSG(ok, "%s: reading the frame back", name);
    CHECK(model_render(name, w, h, cells, frame, &direct, &st) == 0);
    CHECK(via.w == direct.w && via.h == direct.h);
    size_t n = (size_t)via.w * (size_t)via.h * 3, diff = 0;
    for (size_t i = 0; i < n; i++)
        diff += memcmp(&via.rgb[i], &direct.rgb[i], sizeof via.rgb[i]) != 0;
    c5drv_image_free(&via);
    c5_image_free(&direct);
    CHECK_MSG(diff == 0, "%s %dx%d cells %d frame %d: %zu of %zu channels differ", name, w, h, cells, frame, diff, n);
    CHECK_MSG(c.fetches_served == st.fetches && c.fetches == st.fetches && board_st.fetches == st.fetches,
              "%s: fetches served %llu, board register %u, emulated model %llu, direct model %llu", name,
              (unsigned long long)c.fetches_served, c.fetches, (unsigned long long)board_st.fetches,
              (unsigned long long)st.fetches);
    CHECK_MSG(c.cycles == st.cycles && c.samples == st.samples, "%s: counters differ from the model's", name);
    CHECK(c.fetches_served > 0 || cells == 1);
}

TEST(link_frame_default_one_cell) { same_frame("default", 40, 30, 1, 0); }
TEST(link_frame_default_8_cells) { same_frame("default", 40, 30, 2, 0); }
TEST(link_frame_brain_mirrors_27_cells_frame_3) { same_frame("brain_mirrors", 32, 32, 3, 3); }
TEST(link_frame_clouds_lake_8_cells) { same_frame("clouds_lake", 32, 24, 2, 0); }
TEST(link_frame_lobster_tunnel_8_cells) { same_frame("lobster_tunnel", 24, 32, 2, 0); }

TEST(link_identify_and_serial)
{
    link l;
    CHECK_MSG(up(&l, "C5SERIAL42") == C5DRV_OK, "%s", l.msg);
    c5drv_info info;
    int rc = c5drv_identify(l.d, &info);
    down(&l);
    CHECK_INT(rc, C5DRV_OK);
    CHECK_INT(info.id, 0x43554235);
    CHECK_INT(info.major, 1);
    CHECK(strcmp(info.serial, "C5SERIAL42") == 0);
}

TEST(link_open_wrong_serial_not_found)
{
    link l;
    CHECK(c5_link_fixture_up(&l.fx, "ONE") == 0);
    c5drv *d = NULL;
    char msg[256] = "";
    int rc = c5drv_open_usb(C5_USB_VID, C5_USB_PID, "OTHER", &d, msg, sizeof msg);
    c5_link_fixture_down(&l.fx);
    CHECK_INT(rc, C5DRV_E_NOT_FOUND);
    CHECK(d == NULL);
    CHECK_MSG(strstr(msg, "OTHER") != NULL, "message names the serial: %s", msg);
}

/* default at 32x32 in 8 cells with the fault armed after the scene is loaded: the frame's
 * result code, the stall retries and the wall time. */
static int faulted_frame(c5_fault f, unsigned timeout_ms, uint64_t *retries, double *wall, char *msg, size_t cap)
{
    link l;
    if (up(&l, NULL) != C5DRV_OK) {
        snprintf(msg, cap, "%s", l.msg);
        return 1;
    }
    int split[3] = {2, 2, 2};
    int rc = c5drv_load_scene(l.d, c5_builtin_scene_json("default"), NULL, "default", split, 32, 32);
    double t0 = c5_now_s();
    if (rc == C5DRV_OK) {
        c5_emu_set_fault(l.fx.board, &f);
        rc = c5drv_start_frame(l.d, 0);
        if (rc == C5DRV_OK)
            rc = c5drv_wait_frame(l.d, timeout_ms);
    }
    *wall = c5_now_s() - t0;
    c5drv_counters c = {0};
    if (rc == C5DRV_OK)
        c5drv_read_counters(l.d, &c);
    *retries = c.stall_retries;
    snprintf(msg, cap, "%s", c5drv_message(l.d));
    down(&l);
    return rc;
}

#define EXPECT_FAULT(kind, type, nth, repeat, code)                                                    \
    do {                                                                                               \
        uint64_t r;                                                                                    \
        double wall;                                                                                   \
        char m[512];                                                                                   \
        int rc = faulted_frame((c5_fault){kind, type, nth, repeat}, 3000, &r, &wall, m, sizeof m);     \
        CHECK_MSG(rc == (code), "%s expected, got %s: %s", c5drv_strerror(code), c5drv_strerror(rc), m); \
        CHECK_MSG((code) == C5DRV_OK || m[0], "an error without a message");                           \
        CHECK_MSG(wall < 10, "took %.1f s", wall);                                                     \
    } while (0)

TEST(link_fault_one_stall_recovers)
{
    uint64_t retries;
    double wall;
    char m[512];
    int rc = faulted_frame((c5_fault){C5_FAULT_STALL, C5_TLP_DMA_READ, 2, 1}, 60000, &retries, &wall, m, sizeof m);
    CHECK_MSG(rc == C5DRV_OK, "%s: %s", c5drv_strerror(rc), m);
    CHECK_MSG(retries >= 1, "stall_retries %llu", (unsigned long long)retries);
}

TEST(link_fault_persistent_stall) { EXPECT_FAULT(C5_FAULT_STALL, C5_TLP_DMA_READ, 2, C5DRV_STALL_RETRIES + 1, C5DRV_E_STALL); }
TEST(link_fault_short_transfer) { EXPECT_FAULT(C5_FAULT_SHORT, C5_TLP_DMA_READ, 2, 0, C5DRV_E_SHORT); }
TEST(link_fault_timeout) { EXPECT_FAULT(C5_FAULT_TIMEOUT, C5_TLP_INTERRUPT, 2, 0, C5DRV_E_TIMEOUT); }
TEST(link_fault_disconnect_mid_frame) { EXPECT_FAULT(C5_FAULT_DISCONNECT, C5_TLP_DMA_READ, 3, 0, C5DRV_E_DISCONNECTED); }
TEST(link_fault_corrupt_completion) { EXPECT_FAULT(C5_FAULT_CORRUPT, C5_TLP_REG_COMPLETION, 5, 0, C5DRV_E_PROTOCOL); }
TEST(link_fault_corrupt_interrupt) { EXPECT_FAULT(C5_FAULT_CORRUPT, C5_TLP_INTERRUPT, 1, 0, C5DRV_E_PROTOCOL); }
TEST(link_fault_short_frame_buffer_write) { EXPECT_FAULT(C5_FAULT_SHORT, C5_TLP_DMA_WRITE, 1, 0, C5DRV_E_SHORT); }
