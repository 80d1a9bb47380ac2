/* Host link packets (tlp.h). */
#include <stdio.h>
#include <string.h>

#include "tlp.h"

const char *c5_tlp_type_name(unsigned type)
{
    static const char *const names[] = {NULL, "reg_read", "reg_write", "reg_completion", "dma_read",
                                        "dma_completion", "dma_write", "interrupt"};
    return type < sizeof names / sizeof names[0] && names[type] ? names[type] : "unknown";
}

size_t c5_tlp_payload_bytes(const c5_tlp_header_t *h)
{
    switch (h->type) {
    case C5_TLP_REG_WRITE:
    case C5_TLP_DMA_WRITE:
    case C5_TLP_INTERRUPT:
        return h->length;
    case C5_TLP_REG_COMPLETION:
    case C5_TLP_DMA_COMPLETION:
        return h->status == C5_TLP_SC ? h->length : 0;
    default:
        return 0;
    }
}

size_t c5_tlp_put(uint8_t *pkt, c5_tlp_type type, uint8_t tag, c5_tlp_status status, uint32_t length, uint64_t addr)
{
    c5_tlp_header_t h = {.type = type,
                         .tag = tag,
                         .status = status,
                         .sync = C5_TLP_SYNC,
                         .length = length,
                         .addr_lo = (uint32_t)addr,
                         .addr_hi = (uint32_t)(addr >> 32)};
    c5_tlp_header_pack(&h, pkt);
    return C5_TLP_HEADER_BYTES + c5_tlp_payload_bytes(&h);
}

#define WHY(...) (snprintf(why, cap, __VA_ARGS__), -1)
#define WHY_SHORT(...) (snprintf(why, cap, __VA_ARGS__), C5_TLP_SHORT)

int c5_tlp_check(const uint8_t *pkt, size_t len, c5_tlp_header_t *h, char *why, size_t cap)
{
    if (len < C5_TLP_HEADER_BYTES)
        return WHY_SHORT("short transfer: %zu bytes, a header alone is %d", len, C5_TLP_HEADER_BYTES);
    c5_tlp_header_unpack(pkt, h);
    if (h->sync != C5_TLP_SYNC)
        return WHY("bad sync byte 0x%02x (expected 0x%02x): not a cube5 packet", (unsigned)h->sync, C5_TLP_SYNC);
    if (!c5_tlp_header_reserved_zero(pkt))
        return WHY("%s: reserved header bits set", c5_tlp_type_name(h->type));
    const char *name = c5_tlp_type_name(h->type);
    if (h->type < C5_TLP_REG_READ || h->type > C5_TLP_INTERRUPT)
        return WHY("unknown packet type %u", (unsigned)h->type);
    if (h->status != C5_TLP_SC && h->status != C5_TLP_UR && h->status != C5_TLP_CA)
        return WHY("%s: unknown status %u", name, (unsigned)h->status);
    int is_cpl = h->type == C5_TLP_REG_COMPLETION || h->type == C5_TLP_DMA_COMPLETION;
    if (!is_cpl && h->status != C5_TLP_SC)
        return WHY("%s: status %u in a request", name, (unsigned)h->status);
    uint64_t addr = (uint64_t)h->addr_hi << 32 | h->addr_lo;
    int is_reg = h->type <= C5_TLP_REG_COMPLETION;
    if (h->length % 4 || (addr % 4))
        return WHY("%s: length %u or address 0x%llx not a multiple of 4", name, (unsigned)h->length,
                   (unsigned long long)addr);
    if (is_reg || h->type == C5_TLP_INTERRUPT) {
        int ok = h->type == C5_TLP_REG_COMPLETION ? h->length == 0 || (h->length == 4 && h->status == C5_TLP_SC)
                                                  : h->length == 4;
        if (!ok)
            return WHY("%s: length %u, a register packet moves 4 bytes (a write's or an error's completion 0)",
                       name, (unsigned)h->length);
        if (h->addr_hi != 0 || (h->type == C5_TLP_INTERRUPT && h->addr_lo != 0))
            return WHY("%s: address 0x%llx out of range", name, (unsigned long long)addr);
    } else if (h->length == 0 ? !(is_cpl && h->status != C5_TLP_SC) : h->length > C5_TLP_MAX_PAYLOAD) {
        return WHY("%s: length %u outside 4..%u", name, (unsigned)h->length, C5_TLP_MAX_PAYLOAD);
    }
    size_t want = C5_TLP_HEADER_BYTES + c5_tlp_payload_bytes(h);
    if (len < want)
        return WHY_SHORT("short transfer: %s of %zu bytes, %zu received", name, want, len);
    if (len != want)
        return WHY("%s: %zu bytes received, header says %zu", name, len, want);
    return 0;
}
