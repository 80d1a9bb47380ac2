/* The emulated board's USB device through plain libusb (no cube5 driver): enumeration, the
 * serial string, a register read over the bulk pair, two boards side by side, the link faults
 * as libusb reports them, and an idle device that leaves the CPU alone. */
#include <libusb.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "harness.h"
#include "tlp.h"
#include "usb_fixture.h"

#define IN_CAP C5_TLP_MAX_BYTES
#define C5_ID 0x43554235u /* register 0x000: "C5UB" */

static uint8_t inbuf[IN_CAP];

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static int count_boards(libusb_context *ctx)
{
    libusb_device **list;
    ssize_t n = libusb_get_device_list(ctx, &list);
    int found = 0;
    for (ssize_t i = 0; i < n; i++) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) == 0 && dd.idVendor == C5_USB_VID && dd.idProduct == C5_USB_PID)
            found++;
    }
    if (n >= 0)
        libusb_free_device_list(list, 1);
    return n < 0 ? (int)n : found;
}

/* Opens the board with this serial (NULL: the first 1209:0001) and claims interface 0. */
static libusb_device_handle *open_board(libusb_context *ctx, const char *serial)
{
    libusb_device **list;
    libusb_device_handle *found = NULL;
    ssize_t n = libusb_get_device_list(ctx, &list);
    for (ssize_t i = 0; i < n && !found; i++) {
        struct libusb_device_descriptor dd;
        libusb_device_handle *h;
        if (libusb_get_device_descriptor(list[i], &dd) || dd.idVendor != C5_USB_VID || dd.idProduct != C5_USB_PID)
            continue;
        if (libusb_open(list[i], &h))
            continue;
        unsigned char s[128] = "";
        if (!serial || (libusb_get_string_descriptor_ascii(h, dd.iSerialNumber, s, sizeof s) > 0 &&
                        strcmp((char *)s, serial) == 0))
            found = h;
        else
            libusb_close(h);
    }
    if (n >= 0)
        libusb_free_device_list(list, 1);
    if (found && libusb_claim_interface(found, C5_USB_INTERFACE)) {
        libusb_close(found);
        found = NULL;
    }
    return found;
}

static int send_reg_read(libusb_device_handle *h, uint8_t tag, uint32_t addr)
{
    uint8_t pkt[C5_TLP_HEADER_BYTES];
    int len = (int)c5_tlp_put(pkt, C5_TLP_REG_READ, tag, C5_TLP_SC, 4, addr), done = 0;
    int r = libusb_bulk_transfer(h, C5_USB_EP_OUT, pkt, len, &done, 1000);
    return r ? r : done == len ? 0 : LIBUSB_ERROR_IO;
}

/* One bulk IN transfer; its return code, the bytes in *got. */
static int recv_pkt(libusb_device_handle *h, int *got, unsigned timeout_ms)
{
    *got = 0;
    return libusb_bulk_transfer(h, C5_USB_EP_IN, inbuf, IN_CAP, got, timeout_ms);
}

/* Checks that inbuf holds the reg_completion of register 0 with the board's ID. */
static int is_id_completion(int got, uint8_t tag)
{
    c5_tlp_header_t hd;
    char why[160];
    if (c5_tlp_check(inbuf, (size_t)got, &hd, why, sizeof why) != 0) {
        printf("    bad packet: %s\n", why);
        return 0;
    }
    uint32_t v = (uint32_t)inbuf[16] | (uint32_t)inbuf[17] << 8 | (uint32_t)inbuf[18] << 16 | (uint32_t)inbuf[19] << 24;
    return hd.type == C5_TLP_REG_COMPLETION && hd.tag == tag && hd.status == C5_TLP_SC && hd.length == 4 &&
           got == C5_TLP_HEADER_BYTES + 4 && v == C5_ID;
}

/* Fixture, libusb context and an opened, claimed board; the test body runs between. */
typedef struct {
    c5_link_fixture fx;
    libusb_context *ctx;
    libusb_device_handle *h;
} rig;

static int rig_up(rig *r, const char *serial)
{
    memset(r, 0, sizeof *r);
    if (c5_link_fixture_up(&r->fx, serial)) {
        printf("    %s\n", r->fx.msg);
        return -1;
    }
    if (libusb_init(&r->ctx)) {
        printf("    libusb_init failed\n");
        return -1;
    }
    r->h = open_board(r->ctx, serial);
    if (!r->h)
        printf("    no board %s found by libusb\n", serial ? serial : "");
    return r->h ? 0 : -1;
}

static void rig_down(rig *r)
{
    if (r->h) {
        libusb_release_interface(r->h, C5_USB_INTERFACE);
        libusb_close(r->h);
    }
    if (r->ctx)
        libusb_exit(r->ctx);
    c5_link_fixture_down(&r->fx);
}

TEST(usb_raw_enumerate_and_serial)
{
    c5_link_fixture fx;
    int up = c5_link_fixture_up(&fx, "C5RAW-SER1");
    CHECK_MSG(up == 0, "%s", fx.msg);
    libusb_context *ctx = NULL;
    int ok = libusb_init(&ctx) == 0;
    int boards = ok ? count_boards(ctx) : -1;
    libusb_device_handle *h = ok ? open_board(ctx, "C5RAW-SER1") : NULL;
    unsigned char s[64] = "", prod[64] = "";
    struct libusb_config_descriptor *cfg = NULL;
    int nep = -1, ep0 = -1, ep1 = -1, mps = -1;
    if (h) {
        libusb_device *dev = libusb_get_device(h);
        struct libusb_device_descriptor dd;
        libusb_get_device_descriptor(dev, &dd);
        libusb_get_string_descriptor_ascii(h, dd.iSerialNumber, s, sizeof s);
        libusb_get_string_descriptor_ascii(h, dd.iProduct, prod, sizeof prod);
        if (libusb_get_active_config_descriptor(dev, &cfg) == 0 && cfg->bNumInterfaces == 1) {
            const struct libusb_interface_descriptor *id = &cfg->interface[0].altsetting[0];
            nep = id->bNumEndpoints;
            if (nep == 2) {
                ep0 = id->endpoint[0].bEndpointAddress, ep1 = id->endpoint[1].bEndpointAddress;
                mps = id->endpoint[0].wMaxPacketSize;
            }
        }
        libusb_free_config_descriptor(cfg);
        libusb_release_interface(h, C5_USB_INTERFACE);
        libusb_close(h);
    }
    if (ctx)
        libusb_exit(ctx);
    c5_link_fixture_down(&fx);
    CHECK(ok);
    CHECK_INT(boards, 1);
    CHECK(h != NULL);
    CHECK_MSG(strcmp((char *)s, "C5RAW-SER1") == 0, "serial \"%s\"", (char *)s);
    CHECK(prod[0] != 0);
    CHECK_INT(nep, 2);
    CHECK_INT(ep0, C5_USB_EP_OUT);
    CHECK_INT(ep1, C5_USB_EP_IN);
    CHECK_INT(mps, 512);
}

TEST(usb_raw_reg_read_id)
{
    rig r;
    int up = rig_up(&r, NULL);
    int sent = -1, rcv = -1, got = 0, id_ok = 0, loops_ok = 1;
    double ms = 0;
    if (up == 0) {
        sent = send_reg_read(r.h, 7, 0x000);
        rcv = recv_pkt(r.h, &got, 2000);
        id_ok = rcv == 0 && is_id_completion(got, 7);
        /* The round trip, for the record (the notes saw 0.4-0.7 ms). */
        const int n = 200;
        double t0 = now_ms();
        for (int i = 0; i < n && loops_ok; i++)
            loops_ok = send_reg_read(r.h, (uint8_t)i, 0) == 0 && recv_pkt(r.h, &got, 2000) == 0 &&
                       is_id_completion(got, (uint8_t)i);
        ms = (now_ms() - t0) / n;
    }
    rig_down(&r);
    CHECK(up == 0);
    CHECK_INT(sent, 0);
    CHECK_INT(rcv, 0);
    CHECK_MSG(id_ok, "no reg_completion with ID 0x%08x (%d bytes)", C5_ID, got);
    CHECK(loops_ok);
    printf("    reg_read round trip: %.3f ms\n", ms);
}

TEST(usb_raw_two_boards)
{
    c5_link_fixture a, b;
    int upa = c5_link_fixture_up(&a, "C5RAW-A");
    int upb = upa == 0 ? c5_link_fixture_up(&b, "C5RAW-B") : -1;
    libusb_context *ctx = NULL;
    int boards = -1, ra = -1, rb = -1, ga = 0, gb = 0, ida = 0, idb = 0;
    libusb_device_handle *ha = NULL, *hb = NULL;
    if (upb == 0 && libusb_init(&ctx) == 0) {
        boards = count_boards(ctx);
        ha = open_board(ctx, "C5RAW-A");
        hb = open_board(ctx, "C5RAW-B");
        if (ha && hb && ha != hb) {
            /* A request to B, then to A: each answers on its own pipe. */
            if (send_reg_read(hb, 2, 0) == 0 && send_reg_read(ha, 1, 0) == 0) {
                ra = recv_pkt(ha, &ga, 2000);
                ida = ra == 0 && is_id_completion(ga, 1);
                rb = recv_pkt(hb, &gb, 2000);
                idb = rb == 0 && is_id_completion(gb, 2);
            }
        }
        for (libusb_device_handle **h = (libusb_device_handle *[]){ha, hb, NULL}; *h; h++) {
            libusb_release_interface(*h, 0);
            libusb_close(*h);
        }
        libusb_exit(ctx);
    }
    if (upb == 0)
        c5_link_fixture_down(&b);
    if (upa == 0)
        c5_link_fixture_down(&a);
    CHECK_MSG(upa == 0, "%s", a.msg);
    CHECK_MSG(upb == 0, "%s", b.msg);
    CHECK_INT(boards, 2);
    CHECK(ha != NULL && hb != NULL);
    CHECK(libusb_get_device(ha) != libusb_get_device(hb));
    CHECK_INT(ra, 0);
    CHECK_INT(rb, 0);
    CHECK(ida);
    CHECK(idb);
}

TEST(usb_raw_stall_then_clear_halt)
{
    rig r;
    int up = rig_up(&r, NULL);
    int r1 = 99, r2 = 99, rc = 99, r3 = 99, got = 0, id_ok = 0;
    if (up == 0) {
        c5_fault f = {.kind = C5_FAULT_STALL, .type = C5_TLP_REG_COMPLETION, .nth = 1};
        c5_emu_set_fault(r.fx.board, &f);
        send_reg_read(r.h, 9, 0);
        r1 = recv_pkt(r.h, &got, 2000);
        r2 = recv_pkt(r.h, &got, 2000); /* still halted until the host clears it */
        rc = libusb_clear_halt(r.h, C5_USB_EP_IN);
        r3 = recv_pkt(r.h, &got, 2000);
        id_ok = r3 == 0 && is_id_completion(got, 9);
    }
    rig_down(&r);
    CHECK(up == 0);
    CHECK_INT(r1, LIBUSB_ERROR_PIPE);
    CHECK_INT(r2, LIBUSB_ERROR_PIPE);
    CHECK_INT(rc, 0);
    CHECK_INT(r3, 0);
    CHECK(id_ok);
}

TEST(usb_raw_short_transfer)
{
    rig r;
    int up = rig_up(&r, NULL);
    int r1 = 99, got = 0;
    if (up == 0) {
        c5_fault f = {.kind = C5_FAULT_SHORT, .type = 0, .nth = 1};
        c5_emu_set_fault(r.fx.board, &f);
        send_reg_read(r.h, 3, 0);
        r1 = recv_pkt(r.h, &got, 2000);
    }
    rig_down(&r);
    CHECK(up == 0);
    CHECK_INT(r1, 0);
    CHECK_INT(got, (C5_TLP_HEADER_BYTES + 4) / 2);
}

TEST(usb_raw_disconnect)
{
    rig r;
    int up = rig_up(&r, NULL);
    int r1 = 99, r2 = 99, r3 = 99, got = 0;
    double ms = -1;
    if (up == 0) {
        c5_fault f = {.kind = C5_FAULT_DISCONNECT, .type = 0, .nth = 1};
        c5_emu_set_fault(r.fx.board, &f);
        send_reg_read(r.h, 4, 0);
        double t0 = now_ms();
        r1 = recv_pkt(r.h, &got, 5000);
        ms = now_ms() - t0;
        r2 = send_reg_read(r.h, 5, 0);
        r3 = libusb_clear_halt(r.h, C5_USB_EP_IN);
    }
    rig_down(&r); /* must not hang either */
    CHECK(up == 0);
    CHECK_INT(r1, LIBUSB_ERROR_NO_DEVICE);
    CHECK_MSG(ms < 1000, "the disconnect took %.0f ms to show", ms);
    CHECK_INT(r2, LIBUSB_ERROR_NO_DEVICE);
    CHECK_INT(r3, LIBUSB_ERROR_NO_DEVICE);
}

TEST(usb_raw_timeout)
{
    rig r;
    int up = rig_up(&r, NULL);
    int r1 = 99, got = 0;
    double ms = -1;
    if (up == 0) {
        c5_fault f = {.kind = C5_FAULT_TIMEOUT, .type = C5_TLP_REG_COMPLETION, .nth = 1};
        c5_emu_set_fault(r.fx.board, &f);
        send_reg_read(r.h, 6, 0);
        double t0 = now_ms();
        r1 = recv_pkt(r.h, &got, 250);
        ms = now_ms() - t0;
    }
    rig_down(&r);
    CHECK(up == 0);
    CHECK_INT(r1, LIBUSB_ERROR_TIMEOUT);
    CHECK_MSG(ms >= 240 && ms < 1500, "timed out after %.0f ms, 250 asked", ms);
}

TEST(usb_raw_in_with_nothing_pending)
{
    rig r;
    int up = rig_up(&r, NULL);
    int r1 = 99, r2 = 99, got = 0, id_ok = 0;
    double ms = -1;
    if (up == 0) {
        double t0 = now_ms();
        r1 = recv_pkt(r.h, &got, 100);
        ms = now_ms() - t0;
        /* The cancelled URB must not eat the next packet. */
        send_reg_read(r.h, 8, 0);
        r2 = recv_pkt(r.h, &got, 2000);
        id_ok = r2 == 0 && is_id_completion(got, 8);
    }
    rig_down(&r);
    CHECK(up == 0);
    CHECK_INT(r1, LIBUSB_ERROR_TIMEOUT);
    CHECK_MSG(ms >= 95 && ms < 1000, "timed out after %.0f ms, 100 asked", ms);
    CHECK_INT(r2, 0);
    CHECK(id_ok);
}

static void LIBUSB_CALL on_done(struct libusb_transfer *t) { *(int *)t->user_data = 1; }

static double cpu_ms(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e3 + (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e3;
}

/* An IN transfer waits on an idle board while libusb handles events for 300 ms: with the
 * FIFO node the process sleeps (a plain-file node would spin the event loop at 100%). */
TEST(usb_raw_idle_does_not_spin)
{
    rig r;
    int up = rig_up(&r, NULL);
    double used = -1;
    int done = 0, status = -1;
    if (up == 0) {
        struct libusb_transfer *t = libusb_alloc_transfer(0);
        libusb_fill_bulk_transfer(t, r.h, C5_USB_EP_IN, inbuf, IN_CAP, on_done, &done, 0);
        if (libusb_submit_transfer(t) == 0) {
            double c0 = cpu_ms(), t0 = now_ms();
            while (now_ms() - t0 < 300) {
                struct timeval tv = {0, 50000};
                libusb_handle_events_timeout_completed(r.ctx, &tv, NULL);
            }
            used = cpu_ms() - c0;
            libusb_cancel_transfer(t);
            for (int i = 0; i < 100 && !done; i++) {
                struct timeval tv = {0, 20000};
                libusb_handle_events_timeout_completed(r.ctx, &tv, &done);
            }
            status = t->status;
        }
        if (done)
            libusb_free_transfer(t);
    }
    rig_down(&r);
    CHECK(up == 0);
    CHECK(done);
    CHECK_INT(status, LIBUSB_TRANSFER_CANCELLED);
    CHECK_MSG(used >= 0 && used < 100, "%.1f ms of CPU in 300 ms idle", used);
    printf("    idle: %.1f ms of CPU in 300 ms\n", used);
}
