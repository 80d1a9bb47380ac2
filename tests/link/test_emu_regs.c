/* The emulated board's core at the packet level, with no transport: BAR0 semantics
 * (spec/registers.toml), the protocol's refusals (docs/host-protocol.md) and the fault
 * injector (board_emu/emu_board.h). The driver's tests use the same board over libusb. */
#include <string.h>

#include "c5_regs_map.h"
#include "emu_board.h"
#include "harness.h"
#include "tlp.h"

static uint8_t pkt[C5_TLP_MAX_BYTES];

static int send_reg(c5_emu *e, c5_tlp_type type, uint8_t tag, uint32_t off, uint32_t value)
{
    size_t n = c5_tlp_put(pkt, type, tag, C5_TLP_SC, 4, off);
    for (int i = 0; i < 4; i++)
        pkt[C5_TLP_HEADER_BYTES + i] = (uint8_t)(value >> (8 * i));
    return c5_emu_out(e, pkt, n);
}

/* The next packet from the board: its checked header, payload word in *value. */
static int next(c5_emu *e, c5_tlp_header_t *h, uint32_t *value)
{
    size_t len = 0;
    if (!c5_emu_in_wait(e, 1000))
        return C5_EMU_NOTHING;
    int rc = c5_emu_in_pop(e, pkt, sizeof pkt, &len);
    if (rc != C5_EMU_PACKET)
        return rc;
    char why[160];
    if (c5_tlp_check(pkt, len, h, why, sizeof why) != 0)
        return -100;
    *value = len >= 20 ? (uint32_t)pkt[16] | (uint32_t)pkt[17] << 8 | (uint32_t)pkt[18] << 16 | (uint32_t)pkt[19] << 24 : 0;
    return rc;
}

static int read_reg(c5_emu *e, uint32_t off, uint32_t *v, unsigned *status)
{
    static uint8_t tag;
    c5_tlp_header_t h;
    send_reg(e, C5_TLP_REG_READ, ++tag, off, 0);
    int rc = next(e, &h, v);
    if (rc != C5_EMU_PACKET || h.type != C5_TLP_REG_COMPLETION || h.tag != tag)
        return -1;
    *status = h.status;
    return 0;
}

static uint32_t rd(c5_emu *e, uint32_t off)
{
    uint32_t v = 0xDEADBEEF;
    unsigned st = 99;
    return read_reg(e, off, &v, &st) == 0 && st == C5_TLP_SC ? v : 0xDEADBEEF;
}

static int wr(c5_emu *e, uint32_t off, uint32_t v)
{
    c5_tlp_header_t h;
    uint32_t ignored;
    send_reg(e, C5_TLP_REG_WRITE, 7, off, v);
    return next(e, &h, &ignored) == C5_EMU_PACKET && h.type == C5_TLP_REG_COMPLETION && h.tag == 7 ? (int)h.status : -1;
}

TEST(emu_identifies_itself)
{
    c5_emu *e = c5_emu_new("S1");
    CHECK(e);
    CHECK_INT(rd(e, C5_REG_ID_OFFSET), 0x43554235);
    CHECK_INT(rd(e, C5_REG_VERSION_OFFSET), C5_REG_VERSION_RESET);
    CHECK_INT(rd(e, C5_REG_INT_MASK_OFFSET), 0x7);
    CHECK(strcmp(c5_emu_serial(e), "S1") == 0);
    c5_emu_free(e);
}

TEST(emu_register_access_rules)
{
    c5_emu *e = c5_emu_new(NULL);
    /* rw fields keep their bits, reserved bits read 0 */
    CHECK_INT(wr(e, C5_REG_IMAGE_SIZE_OFFSET, 0xFFFFFFFFu), C5_TLP_SC);
    CHECK_INT(rd(e, C5_REG_IMAGE_SIZE_OFFSET), ~C5_REG_IMAGE_SIZE_RESERVED_BITS);
    /* read-only registers ignore writes; write-only bits read 0 */
    CHECK_INT(wr(e, C5_REG_ID_OFFSET, 0), C5_TLP_SC);
    CHECK_INT(rd(e, C5_REG_ID_OFFSET), 0x43554235);
    CHECK_INT(wr(e, C5_REG_DMA_DOORBELL_OFFSET, 1), C5_TLP_SC);
    CHECK_INT(rd(e, C5_REG_DMA_DOORBELL_OFFSET), 0);
    /* binary64 halves are plain 32-bit storage */
    CHECK_INT(wr(e, C5_REG_CAM_FOV_LO_OFFSET, 0x12345678u), C5_TLP_SC);
    CHECK_INT(rd(e, C5_REG_CAM_FOV_LO_OFFSET), 0x12345678u);
    /* control.reset: every register back to its reset value */
    CHECK_INT(wr(e, C5_REG_CONTROL_OFFSET, C5_REG_CONTROL_RESET_MASK), C5_TLP_SC);
    CHECK_INT(rd(e, C5_REG_IMAGE_SIZE_OFFSET), C5_REG_IMAGE_SIZE_RESET);
    CHECK_INT(rd(e, C5_REG_CAM_FOV_LO_OFFSET), C5_REG_CAM_FOV_LO_RESET);
    c5_emu_free(e);
}

TEST(emu_refuses_bad_requests)
{
    c5_emu *e = c5_emu_new(NULL);
    uint32_t v;
    unsigned st;
    /* a hole in BAR0 and an offset past it: unsupported request, no payload */
    CHECK(read_reg(e, 0x1FC, &v, &st) == 0);
    CHECK_INT(st, C5_TLP_UR);
    CHECK(read_reg(e, C5_REG_BAR0_BYTES, &v, &st) == 0);
    CHECK_INT(st, C5_TLP_UR);
    CHECK_INT(wr(e, 0x1FC, 1), C5_TLP_UR);
    /* a misaligned register read: malformed, completer abort with the request's tag */
    size_t n = c5_tlp_put(pkt, C5_TLP_REG_READ, 42, C5_TLP_SC, 4, 0);
    pkt[8] = 2; /* addr_lo = 2 */
    CHECK_INT(c5_emu_out(e, pkt, n), 0);
    c5_tlp_header_t h;
    CHECK_INT(next(e, &h, &v), C5_EMU_PACKET);
    CHECK_INT(h.tag, 42);
    CHECK_INT(h.status, C5_TLP_CA);
    /* garbage (no sync byte) and a board-to-host type sent the wrong way: dropped, unanswered */
    memset(pkt, 0x5A, 32);
    CHECK_INT(c5_emu_out(e, pkt, 32), 0);
    n = c5_tlp_put(pkt, C5_TLP_DMA_WRITE, 1, C5_TLP_SC, 4, 0x1000);
    CHECK_INT(c5_emu_out(e, pkt, n), 0);
    CHECK_INT(c5_emu_in_wait(e, 50), 0);
    /* and the board still answers */
    CHECK_INT(rd(e, C5_REG_ID_OFFSET), 0x43554235);
    c5_emu_free(e);
}

TEST(emu_faults)
{
    c5_emu *e = c5_emu_new(NULL);
    c5_tlp_header_t h;
    uint32_t v;
    size_t len;
    /* stall twice on the second register completion, then deliver it */
    c5_emu_set_fault(e, &(c5_fault){C5_FAULT_STALL, C5_TLP_REG_COMPLETION, 2, 2});
    CHECK_INT(rd(e, C5_REG_ID_OFFSET), 0x43554235);
    send_reg(e, C5_TLP_REG_READ, 9, C5_REG_ID_OFFSET, 0);
    CHECK_INT(c5_emu_in_pop(e, pkt, sizeof pkt, &len), C5_EMU_STALL);
    CHECK_INT(c5_emu_in_pop(e, pkt, sizeof pkt, &len), C5_EMU_STALL);
    CHECK_INT(next(e, &h, &v), C5_EMU_PACKET);
    CHECK_INT(v, 0x43554235);
    /* short: half the packet */
    c5_emu_set_fault(e, &(c5_fault){C5_FAULT_SHORT, 0, 1, 0});
    send_reg(e, C5_TLP_REG_READ, 10, C5_REG_ID_OFFSET, 0);
    CHECK_INT(c5_emu_in_pop(e, pkt, sizeof pkt, &len), C5_EMU_PACKET);
    CHECK_INT(len, 10);
    char why[160];
    CHECK_INT(c5_tlp_check(pkt, len, &h, why, sizeof why), C5_TLP_SHORT);
    /* corrupt: the header no longer checks */
    c5_emu_set_fault(e, &(c5_fault){C5_FAULT_CORRUPT, 0, 1, 0});
    send_reg(e, C5_TLP_REG_READ, 11, C5_REG_ID_OFFSET, 0);
    CHECK_INT(c5_emu_in_pop(e, pkt, sizeof pkt, &len), C5_EMU_PACKET);
    CHECK_INT(c5_tlp_check(pkt, len, &h, why, sizeof why), -1);
    /* timeout: silence from then on */
    c5_emu_set_fault(e, &(c5_fault){C5_FAULT_TIMEOUT, 0, 1, 0});
    send_reg(e, C5_TLP_REG_READ, 12, C5_REG_ID_OFFSET, 0);
    CHECK_INT(c5_emu_in_pop(e, pkt, sizeof pkt, &len), C5_EMU_NOTHING);
    CHECK_INT(c5_emu_in_wait(e, 50), 0);
    c5_emu_free(e);
    /* disconnect: gone both ways */
    e = c5_emu_new(NULL);
    c5_emu_set_fault(e, &(c5_fault){C5_FAULT_DISCONNECT, 0, 1, 0});
    send_reg(e, C5_TLP_REG_READ, 13, C5_REG_ID_OFFSET, 0);
    CHECK_INT(c5_emu_in_pop(e, pkt, sizeof pkt, &len), C5_EMU_GONE);
    CHECK(c5_emu_gone(e));
    CHECK_INT(send_reg(e, C5_TLP_REG_READ, 14, C5_REG_ID_OFFSET, 0), C5_EMU_GONE);
    c5_emu_free(e);
}

TEST(emu_frame_without_descriptor_reports_error)
{
    /* start_frame with scene_length 0: status.error 1, an error interrupt once unmasked */
    c5_emu *e = c5_emu_new(NULL);
    CHECK_INT(wr(e, C5_REG_INT_MASK_OFFSET, 0), C5_TLP_SC);
    CHECK_INT(wr(e, C5_REG_CONTROL_OFFSET, C5_REG_CONTROL_INT_ENABLE_MASK | C5_REG_CONTROL_START_FRAME_MASK), C5_TLP_SC);
    c5_tlp_header_t h;
    uint32_t v = 0;
    CHECK_INT(next(e, &h, &v), C5_EMU_PACKET);
    CHECK_INT(h.type, C5_TLP_INTERRUPT);
    CHECK_INT(v, C5_REG_INT_STATUS_ERROR_MASK);
    uint32_t st = rd(e, C5_REG_STATUS_OFFSET);
    CHECK_INT(c5_reg_status_get_error(st), 1);
    CHECK_INT(c5_reg_status_get_busy(st), 0);
    /* write-one-to-clear */
    CHECK_INT(wr(e, C5_REG_INT_STATUS_OFFSET, C5_REG_INT_STATUS_ERROR_MASK), C5_TLP_SC);
    CHECK_INT(rd(e, C5_REG_INT_STATUS_OFFSET), 0);
    c5_emu_free(e);
}
