/* The driver's transport over libusb-1.0 (docs/host-protocol.md, "Transport"): one packet per
 * bulk transfer on OUT 0x01 / IN 0x81 of interface 0. The handle has its own libusb context
 * so that two handles (or a program's own libusb use) never share event handling. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libusb.h>

#include "c5drv.h"
#include "tlp.h"

_Static_assert(C5DRV_USB_VID == C5_USB_VID && C5DRV_USB_PID == C5_USB_PID, "c5drv.h and tlp.h name one board");

typedef struct {
    libusb_context *ctx;
    libusb_device_handle *h;
    int claimed;
    int out_max; /* wMaxPacketSize of OUT: a packet that fills whole USB packets needs a ZLP */
    char serial[64];
} usb_link;

static int map_err(int e)
{
    switch (e) {
    case LIBUSB_ERROR_TIMEOUT: return C5DRV_E_TIMEOUT;
    case LIBUSB_ERROR_PIPE: return C5DRV_E_STALL;
    case LIBUSB_ERROR_NO_DEVICE: return C5DRV_E_DISCONNECTED;
    case LIBUSB_ERROR_ACCESS:
    case LIBUSB_ERROR_BUSY: return C5DRV_E_ACCESS;
    case LIBUSB_ERROR_NO_MEM: return C5DRV_E_NOMEM;
    default: return C5DRV_E_IO;
    }
}

static int usb_fail(int e, char *msg, size_t cap, const char *what)
{
    snprintf(msg, cap, "%s: %s", what, libusb_strerror((enum libusb_error)e));
    return map_err(e);
}

static void LIBUSB_CALL on_done(struct libusb_transfer *t) { *(int *)t->user_data = 1; }

/* libusb_bulk_transfer, but able to end an OUT transfer with a zero-length packet: without it
 * a packet of a whole number of USB packets would run into the next one (framing is one
 * packet per transfer). Same cancel-and-drain rule on event errors as libusb's own sync API. */
static int bulk(usb_link *u, unsigned char ep, uint8_t *buf, size_t len, int *moved, unsigned ms, int zlp)
{
    struct libusb_transfer *t = libusb_alloc_transfer(0);
    if (!t)
        return LIBUSB_ERROR_NO_MEM;
    int done = 0;
    libusb_fill_bulk_transfer(t, u->h, ep, buf, (int)len, on_done, &done, ms);
    if (zlp)
        t->flags |= LIBUSB_TRANSFER_ADD_ZERO_PACKET;
    int rc = libusb_submit_transfer(t);
    if (rc < 0) {
        libusb_free_transfer(t);
        return rc;
    }
    while (!done) {
        rc = libusb_handle_events_completed(u->ctx, &done);
        if (rc < 0 && rc != LIBUSB_ERROR_INTERRUPTED)
            libusb_cancel_transfer(t); /* then keep handling events until the callback ran */
    }
    *moved = t->actual_length;
    switch (t->status) {
    case LIBUSB_TRANSFER_COMPLETED: rc = 0; break;
    case LIBUSB_TRANSFER_TIMED_OUT: rc = LIBUSB_ERROR_TIMEOUT; break;
    case LIBUSB_TRANSFER_STALL: rc = LIBUSB_ERROR_PIPE; break;
    case LIBUSB_TRANSFER_NO_DEVICE: rc = LIBUSB_ERROR_NO_DEVICE; break;
    case LIBUSB_TRANSFER_OVERFLOW: rc = LIBUSB_ERROR_OVERFLOW; break;
    default: rc = LIBUSB_ERROR_IO; break;
    }
    libusb_free_transfer(t);
    return rc;
}

static int usb_send(void *ctx, const uint8_t *pkt, size_t len, unsigned timeout_ms, char *msg, size_t cap)
{
    usb_link *u = ctx;
    int moved = 0, zlp = u->out_max > 0 && len % (size_t)u->out_max == 0;
    int rc = bulk(u, C5_USB_EP_OUT, (uint8_t *)pkt, len, &moved, timeout_ms, zlp);
    if (rc < 0)
        return usb_fail(rc, msg, cap, "bulk OUT transfer");
    if ((size_t)moved < len) {
        snprintf(msg, cap, "bulk OUT transfer moved %d of %zu bytes", moved, len);
        return C5DRV_E_SHORT;
    }
    return C5DRV_OK;
}

static int usb_recv(void *ctx, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms, char *msg, size_t mcap)
{
    usb_link *u = ctx;
    int moved = 0;
    *got = 0;
    int rc = bulk(u, C5_USB_EP_IN, buf, cap, &moved, timeout_ms, 0);
    if (rc < 0)
        return usb_fail(rc, msg, mcap, "bulk IN transfer");
    *got = (size_t)moved;
    return C5DRV_OK;
}

static int usb_clear_halt(void *ctx, int in, char *msg, size_t cap)
{
    usb_link *u = ctx;
    int rc = libusb_clear_halt(u->h, in ? C5_USB_EP_IN : C5_USB_EP_OUT);
    return rc < 0 ? usb_fail(rc, msg, cap, in ? "clear halt of IN 0x81" : "clear halt of OUT 0x01") : C5DRV_OK;
}

static const char *usb_serial(void *ctx) { return ((usb_link *)ctx)->serial; }

static void usb_close(void *ctx)
{
    usb_link *u = ctx;
    if (!u)
        return;
    if (u->claimed)
        libusb_release_interface(u->h, C5_USB_INTERFACE);
    if (u->h)
        libusb_close(u->h);
    if (u->ctx)
        libusb_exit(u->ctx);
    free(u);
}

/* Opens the first device with vid:pid (and serial, when given); keeps its serial string. */
static int find_board(usb_link *u, uint16_t vid, uint16_t pid, const char *serial, char *msg, size_t cap)
{
    libusb_device **list = NULL;
    ssize_t n = libusb_get_device_list(u->ctx, &list);
    if (n < 0)
        return usb_fail((int)n, msg, cap, "listing USB devices");
    int open_err = 0;
    for (ssize_t i = 0; i < n && !u->h; i++) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) != 0 || dd.idVendor != vid || dd.idProduct != pid)
            continue;
        libusb_device_handle *h = NULL;
        int rc = libusb_open(list[i], &h);
        if (rc < 0) {
            open_err = rc;
            continue;
        }
        unsigned char s[64] = "";
        if (dd.iSerialNumber && libusb_get_string_descriptor_ascii(h, dd.iSerialNumber, s, sizeof s) < 0)
            s[0] = '\0';
        if (serial && strcmp((const char *)s, serial) != 0) {
            libusb_close(h);
            continue;
        }
        u->h = h;
        snprintf(u->serial, sizeof u->serial, "%s", (const char *)s);
        u->out_max = libusb_get_max_packet_size(list[i], C5_USB_EP_OUT);
    }
    libusb_free_device_list(list, 1);
    if (u->h)
        return C5DRV_OK;
    char who[96];
    snprintf(who, sizeof who, "%04x:%04x%s%s", vid, pid, serial ? " with serial " : "", serial ? serial : "");
    if (open_err) {
        snprintf(msg, cap, "board %s found but cannot be opened: %s", who,
                 libusb_strerror((enum libusb_error)open_err));
        return map_err(open_err);
    }
    snprintf(msg, cap, "no board %s on the USB", who);
    return C5DRV_E_NOT_FOUND;
}

int c5drv_open_usb(uint16_t vid, uint16_t pid, const char *serial, c5drv **out, char *msg, size_t cap)
{
    *out = NULL;
    usb_link *u = calloc(1, sizeof *u);
    if (!u) {
        snprintf(msg, cap, "out of memory for the USB transport");
        return C5DRV_E_NOMEM;
    }
    int rc = libusb_init(&u->ctx);
    if (rc < 0) {
        u->ctx = NULL;
        usb_close(u);
        return usb_fail(rc, msg, cap, "libusb_init");
    }
    if ((rc = find_board(u, vid, pid, serial, msg, cap)) != C5DRV_OK) {
        usb_close(u);
        return rc;
    }
    /* a kernel driver bound to the interface (none is expected) is detached while we hold it */
    int e = libusb_set_auto_detach_kernel_driver(u->h, 1);
    if (e < 0 && e != LIBUSB_ERROR_NOT_SUPPORTED) {
        rc = usb_fail(e, msg, cap, "detaching the kernel driver");
        usb_close(u);
        return rc;
    }
    if ((e = libusb_claim_interface(u->h, C5_USB_INTERFACE)) < 0) {
        rc = usb_fail(e, msg, cap, "claiming interface 0 (another program may hold the board)");
        usb_close(u);
        return rc;
    }
    u->claimed = 1;
    c5drv_transport t = {.ctx = u,
                         .send = usb_send,
                         .recv = usb_recv,
                         .clear_halt = usb_clear_halt,
                         .close = usb_close,
                         .serial = usb_serial};
    return c5drv_open(&t, out, msg, cap); /* closes the transport itself on failure */
}
