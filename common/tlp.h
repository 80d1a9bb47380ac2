/* The host link's packets (docs/host-protocol.md): a PCI Express TLP reduced to what one
 * board on one USB pair of bulk endpoints needs. The header's bits are spec/layouts.toml's
 * tlp_header (c5_tlp_header_pack/unpack in the generated c5_layouts.h); this file holds the
 * protocol's constants and the one check both ends apply to every packet they receive. */
#ifndef C5_TLP_H
#define C5_TLP_H

#include <stddef.h>
#include <stdint.h>

#include "c5_layouts.h"

#define C5_TLP_SYNC 0xC5u
#define C5_TLP_MAX_PAYLOAD 65536u                  /* bytes of data in one packet */
#define C5_TLP_MAX_READ 65536u                     /* bytes one dma_read may ask for */
#define C5_TLP_MAX_BYTES (C5_TLP_HEADER_BYTES + C5_TLP_MAX_PAYLOAD) /* one bulk transfer */
#define C5_TLP_READ_WINDOW 64u                     /* dma_reads the board keeps in flight */

/* USB identity of the board: pid.codes' test VID:PID until the board has its own. */
#define C5_USB_VID 0x1209u
#define C5_USB_PID 0x0001u
#define C5_USB_EP_OUT 0x01u                        /* bulk OUT: host -> board */
#define C5_USB_EP_IN 0x81u                         /* bulk IN: board -> host */
#define C5_USB_INTERFACE 0

typedef enum {
    C5_TLP_REG_READ = 1,       /* host -> board: read the BAR0 register at addr_lo */
    C5_TLP_REG_WRITE = 2,      /* host -> board: write it (4-byte payload); answered too */
    C5_TLP_REG_COMPLETION = 3, /* board -> host: the value read (4 bytes) or only a status */
    C5_TLP_DMA_READ = 4,       /* board -> host: send `length` bytes from host address addr */
    C5_TLP_DMA_COMPLETION = 5, /* host -> board: data for a dma_read (the tag's), or a status */
    C5_TLP_DMA_WRITE = 6,      /* board -> host: store the payload at addr (posted: no answer) */
    C5_TLP_INTERRUPT = 7,      /* board -> host: int_status & ~int_mask rose (4-byte payload) */
} c5_tlp_type;

typedef enum {
    C5_TLP_SC = 0, /* successful completion */
    C5_TLP_UR = 1, /* unsupported request: no such register, address outside host memory */
    C5_TLP_CA = 4, /* completer abort: the request was malformed */
} c5_tlp_status;

/* Bytes of payload a packet of this header carries (0 for requests without data and for
 * error completions). */
size_t c5_tlp_payload_bytes(const c5_tlp_header_t *h);

#define C5_TLP_SHORT (-2)
/* Checks a received packet of `len` bytes: sync, reserved bits, a known type, status and
 * length allowed for the type, alignment, and that the transfer holds exactly the header and
 * its payload. 0; C5_TLP_SHORT when the transfer holds less than a header or less than its
 * header announces (a short transfer); -1 for anything else (garbage). A message of at most
 * `cap` bytes goes to `why`. */
int c5_tlp_check(const uint8_t *pkt, size_t len, c5_tlp_header_t *h, char *why, size_t cap);

/* Writes a header into pkt[0..15]; the caller copies the payload after it. Returns the
 * packet's total bytes (header + payload). */
size_t c5_tlp_put(uint8_t *pkt, c5_tlp_type type, uint8_t tag, c5_tlp_status status, uint32_t length, uint64_t addr);

const char *c5_tlp_type_name(unsigned type);

#endif
