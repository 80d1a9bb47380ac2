/* The emulated board: cube5's board model (rtl_model/board.h) behind the host link
 * (docs/host-protocol.md). It holds the BAR0 register file (spec/registers.toml), answers
 * register packets, and runs each frame on its own thread (the board's DSP and processor),
 * which reads the scene descriptor and every cell by DMA from the host and writes the frame
 * buffer back. It knows nothing of USB: board_emu/usb_device.c carries its packets over a
 * umockdev-emulated USB device, and a test can call it directly.
 *
 * Every function is thread-safe: the transport calls c5_emu_out / c5_emu_in_pop from its
 * own thread while the frame thread queues packets. */
#ifndef C5_EMU_BOARD_H
#define C5_EMU_BOARD_H

#include <stddef.h>
#include <stdint.h>

#include "board.h"

typedef struct c5_emu c5_emu;

/* Link faults a test injects (docs/host-protocol.md, fault injection). Each hits the nth
 * packet (1-based) of the given type the board sends; type 0 counts every packet. */
typedef enum {
    C5_FAULT_NONE = 0,
    C5_FAULT_STALL,      /* the IN endpoint halts `repeat` times (0: once) before that packet goes */
    C5_FAULT_SHORT,      /* the packet goes truncated to half its length (a short transfer) */
    C5_FAULT_TIMEOUT,    /* the board falls silent from that packet on: nothing more is sent */
    C5_FAULT_DISCONNECT, /* the device vanishes when that packet would go: every transfer fails */
    C5_FAULT_CORRUPT,    /* the packet goes with its sync byte and tag inverted (garbage) */
} c5_fault_kind;

typedef struct {
    c5_fault_kind kind;
    unsigned type;   /* c5_tlp_type, 0: any */
    unsigned nth;    /* 1-based; 0 counts as 1 */
    unsigned repeat; /* C5_FAULT_STALL: consecutive stalls */
} c5_fault;

/* What c5_emu_in_pop did. */
enum {
    C5_EMU_NOTHING = 0,    /* no packet pending */
    C5_EMU_PACKET = 1,     /* a packet copied into buf (*len bytes; truncated to cap if larger) */
    C5_EMU_STALL = -2,     /* answer this IN transfer with a stall (EPIPE); the packet stays */
    C5_EMU_GONE = -3,      /* the device is disconnected: fail the transfer (ENODEV) */
};

/* A board in its reset state; serial is its USB serial number (NULL: "C5EMU0001"). */
c5_emu *c5_emu_new(const char *serial);
/* Stops a running frame (the frame thread is joined) and frees everything. */
void c5_emu_free(c5_emu *e);
const char *c5_emu_serial(const c5_emu *e);

/* Host -> board: one bulk OUT transfer holding one packet. 0, or C5_EMU_GONE. A malformed
 * packet is answered as the protocol says (an error completion, or dropped), never fatal. */
int c5_emu_out(c5_emu *e, const uint8_t *buf, size_t len);
/* Board -> host: takes the next pending packet for a bulk IN transfer of `cap` bytes. */
int c5_emu_in_pop(c5_emu *e, uint8_t *buf, size_t cap, size_t *len);
/* 1 when c5_emu_in_pop would not return C5_EMU_NOTHING; waits up to timeout_ms for it. */
int c5_emu_in_wait(c5_emu *e, unsigned timeout_ms);
/* Called (from any thread, without the board's lock held) whenever a packet becomes
 * pending or the device vanishes: the USB glue wakes libusb's poll with it. */
void c5_emu_set_notify(c5_emu *e, void (*fn)(void *ctx), void *ctx);

/* Arms one fault (replacing any armed one) and restarts its packet count. */
void c5_emu_set_fault(c5_emu *e, const c5_fault *f);
/* 1 once a C5_FAULT_DISCONNECT has fired. */
int c5_emu_gone(const c5_emu *e);

/* The model's own account of the last completed frame, for tests that compare it with
 * what the driver saw. 0, or -1 when no frame has completed. */
int c5_emu_last_stats(c5_emu *e, c5_board_stats *st);

#endif
