/* The emulated board as a umockdev USB device (usb_device.h). The recipe and the facts behind
 * it are ../shared/notes/usb-emulation.md; board_emu/README.md describes the device.
 *
 * Threads: umockdev runs the ioctl handler on its worker thread; the board's frame thread
 * calls board_notify. One recursive lock (g_lock) guards every device, client and URB queue
 * of the process; the lock order is g_lock, then the board's own lock (the board calls
 * board_notify without its lock, and c5_emu_out may call it from inside the handler).
 *
 * Wake-ups: libusb polls the usbfs fd for POLLOUT and reaps with REAPURBNDELAY. umockdev's
 * node is a plain file, always writable, so libusb would spin; the node is replaced by a FIFO
 * that we keep full (no POLLOUT) and drain by one page exactly while some URB can complete. */
#include "usb_device.h"

#include <errno.h>
#include <fcntl.h>
#include <glib.h>
#include <sys/ioctl.h>
#include <linux/usbdevice_fs.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <umockdev.h>
#include <unistd.h>

#include "tlp.h"

#define FIFO_PAGE 4096
#define SOCKET_PATH_MAX 108 /* sizeof(sockaddr_un.sun_path) */

/* USB descriptors (USB 2.0, chapter 9): one configuration, interface 0 with one alternate
 * setting, vendor class, bulk OUT 0x01 and bulk IN 0x81 of 512 bytes (high speed). */
enum { STR_MANUFACTURER = 1, STR_PRODUCT = 2, STR_SERIAL = 3 };
static const uint8_t dev_desc[18] = {
    18, 1, 0x00, 0x02,         /* bLength, DEVICE, bcdUSB 2.00 */
    0, 0, 0, 64,               /* class/subclass/protocol per interface, ep0 64 bytes */
    C5_USB_VID & 0xff, C5_USB_VID >> 8, C5_USB_PID & 0xff, C5_USB_PID >> 8,
    0x00, 0x01,                /* bcdDevice 1.00 */
    STR_MANUFACTURER, STR_PRODUCT, STR_SERIAL, 1, /* strings, one configuration */
};
static const uint8_t cfg_desc[32] = {
    9, 2, 32, 0, 1, 1, 0, 0x80, 250,       /* CONFIGURATION: 32 bytes, 1 interface, value 1, bus powered 500 mA */
    9, 4, C5_USB_INTERFACE, 0, 2, 0xff, 0, 0, 0, /* INTERFACE 0, alt 0, 2 endpoints, vendor class */
    7, 5, C5_USB_EP_OUT, 2, 0x00, 0x02, 0, /* ENDPOINT 0x01 bulk, 512 */
    7, 5, C5_USB_EP_IN, 2, 0x00, 0x02, 0,  /* ENDPOINT 0x81 bulk, 512 */
};
static const char *const str_manufacturer = "cube5";
static const char *const str_product = "cube5 emulated ray-tracing board";

/* One URB a client submitted and has not reaped yet. */
typedef struct urb_ent {
    UMockdevIoctlData *urb; /* our reference; ->data is the local copy of struct usbdevfs_urb */
    int discarded;          /* DISCARDURB: reaps with -ENOENT */
    int out_status;         /* bulk OUT: consumed at submit, reaps with this status */
    struct urb_ent *next;
} urb_ent;

typedef struct client_st {
    struct c5_usb_device *dev; /* NULL once the device was freed */
    urb_ent *head;
    struct client_st *next;
} client_st;

struct c5_usb_device {
    unsigned id; /* the board's notify context: looked up, never dereferenced after free */
    c5_emu *board;
    int busnum, devnum;
    char node[32];    /* /dev/bus/usb/001/002 */
    char syspath[64]; /* /sys/devices/... as umockdev returned it */
    char *fifo_path;
    int fifo_fd;
    int drained;   /* one page taken out of the FIFO: POLLOUT is up */
    int in_halted; /* IN endpoint halted by a stall until CLEAR_HALT */
    UMockdevIoctlBase *handler;
    client_st *clients;
    struct c5_usb_device *next;
};

static GRecMutex g_lock;
static UMockdevTestbed *g_tb; /* shared by every device of the process */
static unsigned g_tb_refs, g_next_id = 1, g_next_devnum = 2;
static struct c5_usb_device *g_devs;

static struct usbdevfs_urb *urb_of(UMockdevIoctlData *d) { return (struct usbdevfs_urb *)d->data; }

/* ---- the FIFO node ---------------------------------------------------------------------- */

static void fifo_fill(c5_usb_device *d)
{
    static const uint8_t page[FIFO_PAGE];
    while (write(d->fifo_fd, page, sizeof page) > 0) {
    }
    d->drained = 0;
}

static void fifo_drain(c5_usb_device *d)
{
    uint8_t page[FIFO_PAGE];
    if (read(d->fifo_fd, page, sizeof page) > 0)
        d->drained = 1;
}

/* Whether some queued URB of some client would complete on a reap now. */
static int urb_ready(c5_usb_device *d, const urb_ent *u, int gone)
{
    const struct usbdevfs_urb *urb = urb_of(u->urb);
    if (gone || u->discarded || urb->type == USBDEVFS_URB_TYPE_CONTROL || !(urb->endpoint & 0x80))
        return 1;
    return d->in_halted || c5_emu_in_wait(d->board, 0);
}

static int any_ready(c5_usb_device *d)
{
    int gone = c5_emu_gone(d->board);
    for (client_st *c = d->clients; c; c = c->next)
        for (urb_ent *u = c->head; u; u = u->next)
            if (urb_ready(d, u, gone))
                return 1;
    return 0;
}

/* POLLOUT up exactly while a reap would return a URB. Call with g_lock held. */
static void fifo_update(c5_usb_device *d)
{
    if (d->fifo_fd < 0)
        return;
    int ready = any_ready(d);
    if (ready && !d->drained)
        fifo_drain(d);
    else if (!ready && d->drained)
        fifo_fill(d);
}

static void board_notify(void *ctx)
{
    unsigned id = (unsigned)(uintptr_t)ctx;
    g_rec_mutex_lock(&g_lock);
    for (c5_usb_device *d = g_devs; d; d = d->next)
        if (d->id == id)
            fifo_update(d);
    g_rec_mutex_unlock(&g_lock);
}

/* ---- per-client state ------------------------------------------------------------------- */

static void client_unlink(client_st *c)
{
    if (!c->dev)
        return;
    for (client_st **p = &c->dev->clients; *p; p = &(*p)->next)
        if (*p == c) {
            *p = c->next;
            break;
        }
    c5_usb_device *d = c->dev;
    c->dev = NULL;
    fifo_update(d);
}

static void client_free(gpointer p)
{
    client_st *c = p;
    g_rec_mutex_lock(&g_lock);
    client_unlink(c);
    while (c->head) {
        urb_ent *u = c->head;
        c->head = u->next;
        umockdev_ioctl_data_unref(u->urb);
        free(u);
    }
    g_rec_mutex_unlock(&g_lock);
    free(c);
}

static client_st *client_get(c5_usb_device *d, UMockdevIoctlClient *client)
{
    client_st *c = g_object_get_data(G_OBJECT(client), "c5-usb");
    if (c)
        return c;
    c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->dev = d;
    c->next = d->clients;
    d->clients = c;
    g_object_set_data_full(G_OBJECT(client), "c5-usb", c, client_free);
    return c;
}

/* ---- control requests on endpoint 0 ----------------------------------------------------- */

/* Answers the setup packet in buf[0..7] into buf[8..8+cap). Returns the data length, or
 * -EPIPE (a stall: request not supported). */
static int control_answer(c5_usb_device *d, uint8_t *buf, size_t cap)
{
    uint8_t type = buf[0], req = buf[1];
    unsigned value = buf[2] | buf[3] << 8, windex = buf[4] | buf[5] << 8, wlength = buf[6] | buf[7] << 8;
    uint8_t out[256];
    size_t n = 0;
    (void)windex;
    if (type == 0x80 && req == 6) { /* GET_DESCRIPTOR, standard, device */
        unsigned dt = value >> 8, idx = value & 0xff;
        if (dt == 1) {
            memcpy(out, dev_desc, n = sizeof dev_desc);
        } else if (dt == 2 && idx == 0) {
            memcpy(out, cfg_desc, n = sizeof cfg_desc);
        } else if (dt == 3 && idx == 0) {
            const uint8_t langs[4] = {4, 3, 0x09, 0x04}; /* English (US) */
            memcpy(out, langs, n = 4);
        } else if (dt == 3 && idx <= STR_SERIAL) {
            const char *s = idx == STR_MANUFACTURER ? str_manufacturer
                            : idx == STR_PRODUCT    ? str_product
                                                    : c5_emu_serial(d->board);
            size_t len = strlen(s);
            if (len > 126)
                len = 126;
            out[0] = (uint8_t)(2 + 2 * len), out[1] = 3;
            for (size_t i = 0; i < len; i++)
                out[2 + 2 * i] = (uint8_t)s[i], out[3 + 2 * i] = 0;
            n = 2 + 2 * len;
        } else {
            return -EPIPE;
        }
    } else if (type == 0x80 && req == 0) { /* GET_STATUS (device): bus powered, no wakeup */
        out[0] = out[1] = 0, n = 2;
    } else if (type == 0x80 && req == 8) { /* GET_CONFIGURATION */
        out[0] = 1, n = 1;
    } else {
        return -EPIPE;
    }
    if (n > wlength)
        n = wlength;
    if (n > cap)
        n = cap;
    memcpy(buf + 8, out, n);
    return (int)n;
}

/* ---- the ioctl handler ------------------------------------------------------------------ */

static void complete(UMockdevIoctlClient *client, int err)
{
    umockdev_ioctl_client_complete(client, err ? -1 : 0, err);
}

/* Reads the unsigned int the argument points to (CLAIMINTERFACE, CLEAR_HALT, ...). */
static int arg_uint(UMockdevIoctlData *arg, unsigned *v)
{
    UMockdevIoctlData *p = umockdev_ioctl_data_resolve(arg, 0, sizeof(unsigned), NULL);
    if (!p)
        return -1;
    memcpy(v, p->data, sizeof *v);
    umockdev_ioctl_data_unref(p);
    return 0;
}

static int do_submit(c5_usb_device *d, client_st *c, UMockdevIoctlData *arg)
{
    UMockdevIoctlData *ud = umockdev_ioctl_data_resolve(arg, 0, sizeof(struct usbdevfs_urb), NULL);
    if (!ud)
        return EFAULT;
    struct usbdevfs_urb *urb = urb_of(ud);
    int err = 0, out_status = 0;
    int is_ctl = urb->type == USBDEVFS_URB_TYPE_CONTROL && urb->endpoint == 0;
    int is_bulk = urb->type == USBDEVFS_URB_TYPE_BULK &&
                  (urb->endpoint == C5_USB_EP_OUT || urb->endpoint == C5_USB_EP_IN);
    if (!is_ctl && !is_bulk)
        err = EINVAL;
    else if (urb->buffer_length < 0 || (is_ctl && urb->buffer_length < 8))
        err = EINVAL;
    else if (is_bulk && urb->endpoint == C5_USB_EP_OUT) {
        /* Hand the packet to the board at once: its answer can be ready when the IN URB
         * comes. The URB itself completes on the next reap. */
        UMockdevIoctlData *b = NULL;
        if (urb->buffer_length > 0) {
            b = umockdev_ioctl_data_resolve(ud, G_STRUCT_OFFSET(struct usbdevfs_urb, buffer),
                                            (gsize)urb->buffer_length, NULL);
            if (!b)
                err = EFAULT;
        }
        if (!err) {
            int r = c5_emu_out(d->board, b ? b->data : (const uint8_t *)"", (size_t)urb->buffer_length);
            if (r == C5_EMU_GONE)
                err = ENODEV;
            urb = urb_of(ud);
            urb->actual_length = urb->buffer_length;
            out_status = 0;
        }
        if (b)
            umockdev_ioctl_data_unref(b);
    }
    if (err) {
        umockdev_ioctl_data_unref(ud);
        return err;
    }
    urb_ent *u = calloc(1, sizeof *u);
    if (!u) {
        umockdev_ioctl_data_unref(ud);
        return ENOMEM;
    }
    u->urb = ud; /* keeps the resolve's reference */
    u->out_status = out_status;
    urb_ent **tail = &c->head;
    while (*tail)
        tail = &(*tail)->next;
    *tail = u;
    return 0;
}

/* Completes URB u (still queued) if it can complete now: fills its status, length and (IN,
 * control) buffer. 1 when it completed, 0 when it must wait. */
static int try_complete(c5_usb_device *d, urb_ent *u, int gone)
{
    struct usbdevfs_urb *urb = urb_of(u->urb);
    if (u->discarded) {
        urb->status = -ENOENT;
        urb->actual_length = 0;
        return 1;
    }
    if (gone) {
        urb->status = -ENODEV;
        urb->actual_length = 0;
        return 1;
    }
    if (urb->type == USBDEVFS_URB_TYPE_CONTROL) {
        UMockdevIoctlData *b = umockdev_ioctl_data_resolve(u->urb, G_STRUCT_OFFSET(struct usbdevfs_urb, buffer),
                                                           (gsize)urb->buffer_length, NULL);
        urb = urb_of(u->urb);
        if (!b) {
            urb->status = -EFAULT;
            urb->actual_length = 0;
            return 1;
        }
        int n = (b->data[0] & 0x80) ? control_answer(d, b->data, (size_t)urb->buffer_length - 8) : -EPIPE;
        urb->status = n < 0 ? n : 0;
        urb->actual_length = n < 0 ? 0 : n;
        umockdev_ioctl_data_unref(b);
        return 1;
    }
    if (!(urb->endpoint & 0x80)) {
        urb->status = u->out_status;
        return 1;
    }
    /* bulk IN */
    if (d->in_halted) {
        urb->status = -EPIPE;
        urb->actual_length = 0;
        return 1;
    }
    if (!c5_emu_in_wait(d->board, 0))
        return 0;
    size_t cap = (size_t)urb->buffer_length, len = 0;
    uint8_t *tmp = malloc(cap ? cap : 1);
    if (!tmp)
        return 0;
    int r = c5_emu_in_pop(d->board, tmp, cap, &len);
    int done = 1;
    if (r == C5_EMU_PACKET) {
        size_t n = len < cap ? len : cap;
        /* Only the bytes written: umockdev loads and writes back what is resolved. */
        UMockdevIoctlData *b =
            n ? umockdev_ioctl_data_resolve(u->urb, G_STRUCT_OFFSET(struct usbdevfs_urb, buffer), n, NULL) : NULL;
        urb = urb_of(u->urb);
        if (n && !b) {
            urb->status = -EFAULT;
            urb->actual_length = 0;
        } else {
            if (b)
                memcpy(b->data, tmp, n);
            urb->status = len > cap ? -EOVERFLOW : 0; /* babble: the device sent more than asked */
            urb->actual_length = (int)n;
        }
        if (b)
            umockdev_ioctl_data_unref(b);
    } else if (r == C5_EMU_STALL) {
        d->in_halted = 1;
        urb->status = -EPIPE;
        urb->actual_length = 0;
    } else if (r == C5_EMU_GONE) {
        urb->status = -ENODEV;
        urb->actual_length = 0;
    } else {
        done = 0;
    }
    free(tmp);
    return done;
}

static int do_reap(c5_usb_device *d, client_st *c, UMockdevIoctlData *arg)
{
    int gone = c5_emu_gone(d->board);
    urb_ent **pick = NULL;
    /* Discarded URBs first (libusb waits for them to finish a cancellation), then in order. */
    for (urb_ent **p = &c->head; *p && !pick; p = &(*p)->next)
        if ((*p)->discarded)
            pick = p;
    for (urb_ent **p = &c->head; *p && !pick; p = &(*p)->next)
        if (try_complete(d, *p, gone))
            pick = p;
    if (!pick)
        return gone ? ENODEV : EAGAIN;
    urb_ent *u = *pick;
    if (u->discarded)
        try_complete(d, u, gone);
    *pick = u->next;
    UMockdevIoctlData *ptr = umockdev_ioctl_data_resolve(arg, 0, sizeof(void *), NULL);
    int err = 0;
    if (!ptr || !umockdev_ioctl_data_set_ptr(ptr, 0, u->urb))
        err = EFAULT;
    if (ptr)
        umockdev_ioctl_data_unref(ptr);
    umockdev_ioctl_data_unref(u->urb);
    free(u);
    return err;
}

static int do_discard(client_st *c, UMockdevIoctlData *arg)
{
    gulong addr;
    memcpy(&addr, arg->data, sizeof addr);
    for (urb_ent *u = c->head; u; u = u->next)
        if (u->urb->client_addr == addr && !u->discarded) {
            u->discarded = 1;
            return 0;
        }
    return EINVAL;
}

static gboolean handle_ioctl(UMockdevIoctlBase *handler, UMockdevIoctlClient *client, gpointer ctx)
{
    (void)handler;
    unsigned id = (unsigned)(uintptr_t)ctx;
    gulong req = umockdev_ioctl_client_get_request(client);
    UMockdevIoctlData *arg = umockdev_ioctl_client_get_arg(client);
    int err = 0;

    g_rec_mutex_lock(&g_lock);
    c5_usb_device *d = g_devs;
    while (d && d->id != id)
        d = d->next;
    client_st *c = d ? client_get(d, client) : NULL;
    if (!d) {
        err = ENODEV;
    } else if (!c) {
        err = ENOMEM;
    } else if (c5_emu_gone(d->board) && req != USBDEVFS_REAPURBNDELAY && req != USBDEVFS_REAPURB) {
        err = ENODEV; /* the device vanished: every request fails as on a real unplug */
    } else {
        unsigned v = 0;
        switch (req) {
        case USBDEVFS_GET_CAPABILITIES: {
            UMockdevIoctlData *p = umockdev_ioctl_data_resolve(arg, 0, sizeof(uint32_t), NULL);
            if (p) {
                /* Scatter-gather: libusb sends each transfer as one URB. */
                uint32_t caps = USBDEVFS_CAP_BULK_SCATTER_GATHER | USBDEVFS_CAP_NO_PACKET_SIZE_LIM;
                memcpy(p->data, &caps, sizeof caps);
                umockdev_ioctl_data_unref(p);
            } else {
                err = EFAULT;
            }
            break;
        }
        case USBDEVFS_CLAIMINTERFACE:
        case USBDEVFS_RELEASEINTERFACE:
            if (arg_uint(arg, &v))
                err = EFAULT;
            else if (v != C5_USB_INTERFACE)
                err = ENOENT;
            break;
        case USBDEVFS_SETINTERFACE: {
            UMockdevIoctlData *p = umockdev_ioctl_data_resolve(arg, 0, sizeof(struct usbdevfs_setinterface), NULL);
            if (!p) {
                err = EFAULT;
                break;
            }
            struct usbdevfs_setinterface si;
            memcpy(&si, p->data, sizeof si);
            umockdev_ioctl_data_unref(p);
            if (si.interface != C5_USB_INTERFACE || si.altsetting != 0)
                err = EINVAL;
            break;
        }
        case USBDEVFS_CLEAR_HALT:
            if (arg_uint(arg, &v))
                err = EFAULT;
            else if (v == C5_USB_EP_IN)
                d->in_halted = 0;
            else if (v != C5_USB_EP_OUT && v != 0)
                err = ENOENT;
            break;
        case USBDEVFS_RESET:
            d->in_halted = 0;
            break;
        case USBDEVFS_SETCONFIGURATION:
            if (arg_uint(arg, &v))
                err = EFAULT;
            else if (v != 1)
                err = EINVAL;
            break;
        case USBDEVFS_GETDRIVER:
        case USBDEVFS_IOCTL:
            err = ENODATA; /* no kernel driver bound */
            break;
        case USBDEVFS_DISCONNECT_CLAIM:
            break;
        case USBDEVFS_SUBMITURB:
            err = do_submit(d, c, arg);
            break;
        case USBDEVFS_REAPURBNDELAY:
            err = do_reap(d, c, arg);
            break;
        case USBDEVFS_DISCARDURB:
            err = do_discard(c, arg);
            break;
        default:
            err = ENOTTY;
            break;
        }
    }
    if (d)
        fifo_update(d);
    g_rec_mutex_unlock(&g_lock);
    complete(client, err);
    return TRUE;
}

/* ---- device life ------------------------------------------------------------------------ */

static void hex(char *dst, const uint8_t *src, size_t n)
{
    for (size_t i = 0; i < n; i++)
        sprintf(dst + 2 * i, "%02x", src[i]);
}

/* The testbed's directory must be short: the ioctl socket $UMOCKDEV_DIR/ioctl/dev/bus/usb/...
 * has to fit in sun_path. glib reads TMPDIR once per process, so a long TMPDIR is replaced by
 * /tmp around the first testbed_new only. */
static UMockdevTestbed *testbed_get(char *msg, size_t cap)
{
    if (g_tb) {
        g_tb_refs++;
        return g_tb;
    }
    const char *tmp = getenv("TMPDIR");
    char *saved = tmp ? strdup(tmp) : NULL;
    int swapped = tmp && strlen(tmp) > 40;
    if (swapped)
        setenv("TMPDIR", "/tmp", 1);
    g_tb = umockdev_testbed_new();
    if (swapped)
        setenv("TMPDIR", saved, 1);
    free(saved);
    if (!g_tb) {
        snprintf(msg, cap, "umockdev_testbed_new failed");
        return NULL;
    }
    char *root = umockdev_testbed_get_root_dir(g_tb);
    size_t len = strlen(root) + strlen("/ioctl/dev/bus/usb/001/002");
    if (len >= SOCKET_PATH_MAX) {
        snprintf(msg, cap, "umockdev testbed %s: socket path of %zu characters is over %d (point TMPDIR at a short directory)",
                 root, len, SOCKET_PATH_MAX - 1);
        g_free(root);
        g_clear_object(&g_tb);
        return NULL;
    }
    g_free(root);
    g_tb_refs = 1;
    return g_tb;
}

static void testbed_put(void)
{
    if (g_tb && --g_tb_refs == 0)
        g_clear_object(&g_tb);
}

const char *c5_usb_device_node(const c5_usb_device *d) { return d->node; }
int c5_usb_device_busnum(const c5_usb_device *d) { return d->busnum; }
int c5_usb_device_devnum(const c5_usb_device *d) { return d->devnum; }

/* Replaces umockdev's plain-file node by a FIFO held full (see the top of this file). */
static int make_fifo(c5_usb_device *d, char *msg, size_t cap)
{
    char *root = umockdev_testbed_get_root_dir(g_tb);
    d->fifo_path = g_strdup_printf("%s%s", root, d->node);
    g_free(root);
    unlink(d->fifo_path);
    if (mkfifo(d->fifo_path, 0666) != 0 || (d->fifo_fd = open(d->fifo_path, O_RDWR | O_NONBLOCK | O_CLOEXEC)) < 0) {
        snprintf(msg, cap, "%s: %s", d->fifo_path, strerror(errno));
        return -1;
    }
    fifo_fill(d);
    return 0;
}

c5_usb_device *c5_usb_device_new(c5_emu *board, char *msg, size_t cap)
{
    c5_usb_device *d = calloc(1, sizeof *d);
    if (!d) {
        snprintf(msg, cap, "out of memory");
        return NULL;
    }
    d->board = board;
    d->fifo_fd = -1;
    g_rec_mutex_lock(&g_lock);
    if (!testbed_get(msg, cap)) {
        g_rec_mutex_unlock(&g_lock);
        free(d);
        return NULL;
    }
    d->id = g_next_id++;
    d->busnum = 1;
    d->devnum = (int)g_next_devnum++;
    if (g_next_devnum > 127)
        g_next_devnum = 2;
    snprintf(d->node, sizeof d->node, "/dev/bus/usb/%03d/%03d", d->busnum, d->devnum);

    char desc[2 * (sizeof dev_desc + sizeof cfg_desc) + 1];
    hex(desc, dev_desc, sizeof dev_desc);
    hex(desc + 2 * sizeof dev_desc, cfg_desc, sizeof cfg_desc);
    const char *serial = c5_emu_serial(board);
    char *rec = g_strdup_printf("P: /devices/pci0000:00/0000:00:14.0/usb%d/%d-%d\n"
                                "N: bus/usb/%03d/%03d\n"
                                "E: SUBSYSTEM=usb\n"
                                "E: DEVTYPE=usb_device\n"
                                "E: DEVNAME=%s\n"
                                "E: BUSNUM=%03d\n"
                                "E: DEVNUM=%03d\n"
                                "E: ID_VENDOR_ID=%04x\n"
                                "E: ID_MODEL_ID=%04x\n"
                                "E: ID_SERIAL_SHORT=%s\n"
                                "A: busnum=%d\\n\n"
                                "A: devnum=%d\\n\n"
                                "A: speed=480\\n\n"
                                "A: bConfigurationValue=1\\n\n"
                                "A: bNumConfigurations=1\\n\n"
                                "A: idVendor=%04x\\n\n"
                                "A: idProduct=%04x\\n\n"
                                "A: manufacturer=%s\\n\n"
                                "A: product=%s\\n\n"
                                "A: serial=%s\\n\n"
                                "H: descriptors=%s\n",
                                d->busnum, d->busnum, d->devnum, d->busnum, d->devnum, d->node, d->busnum, d->devnum,
                                C5_USB_VID, C5_USB_PID, serial, d->busnum, d->devnum, C5_USB_VID, C5_USB_PID,
                                str_manufacturer, str_product, serial, desc);
    GError *err = NULL;
    int ok = umockdev_testbed_add_from_string(g_tb, rec, &err);
    g_free(rec);
    if (!ok) {
        snprintf(msg, cap, "umockdev: adding the device failed: %s", err ? err->message : "?");
        g_clear_error(&err);
        goto fail;
    }
    snprintf(d->syspath, sizeof d->syspath, "/sys/devices/pci0000:00/0000:00:14.0/usb%d/%d-%d", d->busnum,
             d->busnum, d->devnum);
    if (make_fifo(d, msg, cap))
        goto fail;
    d->handler = umockdev_ioctl_base_new();
    g_signal_connect(d->handler, "handle-ioctl", G_CALLBACK(handle_ioctl), (gpointer)(uintptr_t)d->id);
    if (!umockdev_testbed_attach_ioctl(g_tb, d->node, d->handler, &err)) {
        snprintf(msg, cap, "umockdev: attaching the ioctl handler to %s failed: %s", d->node,
                 err ? err->message : "?");
        g_clear_error(&err);
        goto fail;
    }
    d->next = g_devs;
    g_devs = d;
    g_rec_mutex_unlock(&g_lock);
    c5_emu_set_notify(board, board_notify, (void *)(uintptr_t)d->id);
    return d;
fail:
    if (d->handler)
        g_object_unref(d->handler);
    if (d->syspath[0])
        umockdev_testbed_remove_device(g_tb, d->syspath);
    if (d->fifo_fd >= 0)
        close(d->fifo_fd);
    g_free(d->fifo_path);
    testbed_put();
    g_rec_mutex_unlock(&g_lock);
    free(d);
    return NULL;
}

void c5_usb_device_free(c5_usb_device *d)
{
    if (!d)
        return;
    c5_emu_set_notify(d->board, NULL, NULL);
    g_rec_mutex_lock(&g_lock);
    for (c5_usb_device **p = &g_devs; *p; p = &(*p)->next)
        if (*p == d) {
            *p = d->next;
            break;
        }
    while (d->clients)
        client_unlink(d->clients);
    g_rec_mutex_unlock(&g_lock);
    /* Outside the lock: detaching waits for umockdev's worker, which may be in handle_ioctl. */
    umockdev_testbed_detach_ioctl(g_tb, d->node, NULL);
    g_rec_mutex_lock(&g_lock);
    umockdev_testbed_remove_device(g_tb, d->syspath);
    g_object_unref(d->handler);
    close(d->fifo_fd);
    unlink(d->fifo_path);
    g_free(d->fifo_path);
    testbed_put();
    g_rec_mutex_unlock(&g_lock);
    free(d);
}
