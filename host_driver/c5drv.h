/* cube5's host driver: the board as a PCI-style device (BAR0 registers, DMA, interrupts)
 * carried over USB bulk endpoints (docs/host-protocol.md). The core speaks the protocol
 * through a c5drv_transport and does not know what carries it: c5drv_open_usb gives it
 * libusb, a test may give it anything that moves packets.
 *
 * Every call returns C5DRV_OK (0) or a negative c5drv_status; c5drv_message says what
 * happened in words. A handle is used by one thread at a time.
 *
 * This header is the installed public API (libc5drv, pkg-config c5drv): it includes only
 * standard headers and the handle is opaque, so a program needs nothing of cube5's source
 * tree. Register offsets for c5drv_reg_read/write are in the installed c5_regs_map.h. */
#ifndef C5_DRV_H
#define C5_DRV_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The board's USB identity (pid.codes test VID:PID), what c5drv_open_usb looks for. */
#define C5DRV_USB_VID 0x1209u
#define C5DRV_USB_PID 0x0001u

/* A frame as floats: linear RGB, w * h * 3 values, row-major, top row first. */
typedef struct {
    int w, h;
    float *rgb;
} c5drv_image;

/* Frees the pixels of an image c5drv_read_frame filled and zeroes it (NULL or a zeroed image:
 * nothing happens). */
void c5drv_image_free(c5drv_image *img);

typedef enum {
    C5DRV_OK = 0,
    C5DRV_E_ARG = -1,          /* a bad argument */
    C5DRV_E_NOT_FOUND = -2,    /* no board with that VID:PID (and serial) */
    C5DRV_E_ACCESS = -3,       /* the board is there but cannot be opened or claimed */
    C5DRV_E_IO = -4,           /* any other transport error */
    C5DRV_E_TIMEOUT = -5,      /* the board did not answer in time */
    C5DRV_E_STALL = -6,        /* an endpoint stayed halted after C5DRV_STALL_RETRIES clear-halts */
    C5DRV_E_SHORT = -7,        /* a transfer moved fewer bytes than its packet holds */
    C5DRV_E_DISCONNECTED = -8, /* the board went away */
    C5DRV_E_PROTOCOL = -9,     /* the board sent garbage: a malformed or unexpected packet */
    C5DRV_E_BOARD = -10,       /* the board stopped the frame (status.error, named in the message) */
    C5DRV_E_VERSION = -11,     /* not a cube5 board, or a register-map major this driver does not know */
    C5DRV_E_STATE = -12,       /* out of order: no scene loaded, no frame started or completed */
    C5DRV_E_NOMEM = -13,
    C5DRV_E_SCENE = -14,       /* the scene or its volume cannot be loaded or does not fit the board */
} c5drv_status;

#define C5DRV_STALL_RETRIES 3  /* clear-halts of one endpoint before C5DRV_E_STALL */
#define C5DRV_IO_TIMEOUT_MS 2000 /* one register access or one packet of a transfer */

/* Moves whole packets (docs/host-protocol.md): one packet per transfer each way. Each
 * returns C5DRV_OK or a c5drv_status, with a message in msg for errors. */
typedef struct {
    void *ctx;
    int (*send)(void *ctx, const uint8_t *pkt, size_t len, unsigned timeout_ms, char *msg, size_t cap);
    /* one IN transfer into buf (cap >= C5_TLP_MAX_BYTES); *got = bytes received.
     * C5DRV_E_TIMEOUT when nothing arrived in timeout_ms. */
    int (*recv)(void *ctx, uint8_t *buf, size_t cap, size_t *got, unsigned timeout_ms, char *msg, size_t mcap);
    /* clears a halt of the IN (in = 1) or OUT endpoint */
    int (*clear_halt)(void *ctx, int in, char *msg, size_t cap);
    void (*close)(void *ctx);
    /* The board's serial number for c5drv_identify (USB: iSerialNumber), or NULL when the
     * transport has none (this op may itself be NULL). */
    const char *(*serial)(void *ctx);
} c5drv_transport;

typedef struct c5drv c5drv;

/* The board with this VID:PID and, when serial is not NULL, this serial number. On failure
 * *out is NULL and msg (cap bytes) says why. */
int c5drv_open_usb(uint16_t vid, uint16_t pid, const char *serial, c5drv **out, char *msg, size_t cap);
/* The driver over any transport; the handle owns it (close is called by c5drv_close). */
int c5drv_open(const c5drv_transport *t, c5drv **out, char *msg, size_t cap);
void c5drv_close(c5drv *d);

const char *c5drv_strerror(int code);
/* The message of the last call on this handle ("" after success). */
const char *c5drv_message(const c5drv *d);

typedef struct {
    uint32_t id;                  /* register id: 0x43554235 */
    unsigned major, minor;        /* register map version */
    char serial[64];              /* USB serial number ("" over a transport without one) */
} c5drv_info;

/* Checks id and version; refuses a board that is not cube5's (C5DRV_E_VERSION). */
int c5drv_identify(c5drv *d, c5drv_info *info);
/* control.reset: every register to its reset value; a running frame is abandoned. */
int c5drv_reset(c5drv *d);

/* Loads a scene (JSON text, docs/scene-format.md) and its volume into host memory: the
 * super volume, cut into the board's cells for the split `cells` (NULL: 1x1x1), the empty
 * flags and the scene descriptor. width/height > 0 override the scene's image size.
 * base_dir resolves relative volume paths (NULL: cwd); `what` names the scene in messages. */
int c5drv_load_scene(c5drv *d, const char *json, const char *base_dir, const char *what, const int cells[3],
                     int width, int height);
/* Writes frame `frame`'s camera and the descriptors, unmasks the interrupts and starts it. */
int c5drv_start_frame(c5drv *d, int frame);
/* Serves the board's DMA reads (scene descriptor, cells) and takes its frame-buffer writes
 * until the frame completes, the board reports an error, or timeout_ms passes. */
int c5drv_wait_frame(c5drv *d, unsigned timeout_ms);
/* The completed frame as the model converts it (frame_acc UQ20.12 -> float), into *out,
 * which is overwritten (zeroed on failure; C5DRV_E_ARG when NULL); free it with
 * c5drv_image_free. */
int c5drv_read_frame(c5drv *d, c5drv_image *out);
/* The raw frame buffer (3 words a pixel, frame_acc UQ20.12); valid until the next frame. */
const uint32_t *c5drv_frame_words(const c5drv *d, int *w, int *h);

typedef struct {
    /* the board's counters (registers cnt_*), snapshot of the last frame */
    uint32_t fetches, rays, bus_packets, spills;
    uint64_t cycles, samples;
    /* what this driver did for the last frame */
    uint64_t fetches_served;  /* doorbells rung: cells handed to the board */
    uint64_t dma_reads;       /* dma_read requests served (descriptor and cells) */
    uint64_t bytes_served;    /* bytes sent in dma_completions */
    uint64_t cell_bytes;      /* the part of bytes_served that was cell data (for MB/s) */
    uint64_t fb_bytes;        /* bytes of frame buffer received */
    uint64_t interrupts;      /* interrupt packets received */
    uint64_t stall_retries;   /* clear-halts that recovered a stalled endpoint */
    double cell_upload_s;     /* wall time from each doorbell to the cell's last completion */
    double frame_s;           /* wall time from start_frame to frame_done */
} c5drv_counters;

int c5drv_read_counters(c5drv *d, c5drv_counters *c);

/* Register access for tools and tests (offsets: C5_REG_*_OFFSET in c5_regs_map.h,
 * docs/register-map.md). */
int c5drv_reg_read(c5drv *d, uint32_t offset, uint32_t *value);
int c5drv_reg_write(c5drv *d, uint32_t offset, uint32_t value);

#ifdef __cplusplus
}
#endif

#endif
