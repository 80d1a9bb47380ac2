/* Harness: the host protocol's packet check (common/tlp.c), which the driver and the
 * emulated board apply to every packet they receive. Promises: 0, C5_TLP_SHORT or -1 with a
 * one-line reason; an accepted packet is exactly its header and payload, and c5_tlp_put
 * writes the same 16 header bytes back from the fields the check read. */
#include "fuzz.h"
#include "tlp.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    c5_tlp_header_t h;
    char why[256];
    why[0] = 0;
    int rc = c5_tlp_check(data, size, &h, why, sizeof why);
    c5_fuzz_expect(rc == 0 || rc == -1 || rc == C5_TLP_SHORT, "0, -1 or C5_TLP_SHORT");
    if (rc != 0) {
        c5_fuzz_expect(c5_fuzz_one_line(why, sizeof why), "a one-line reason");
        return 0;
    }
    c5_fuzz_expect(size == C5_TLP_HEADER_BYTES + c5_tlp_payload_bytes(&h), "header plus payload, nothing else");
    uint8_t again[C5_TLP_HEADER_BYTES];
    uint64_t addr = (uint64_t)h.addr_hi << 32 | h.addr_lo;
    c5_tlp_put(again, (c5_tlp_type)h.type, (uint8_t)h.tag, (c5_tlp_status)h.status, h.length, addr);
    c5_fuzz_expect(memcmp(again, data, C5_TLP_HEADER_BYTES) == 0, "c5_tlp_put rebuilds an accepted header");
    return 0;
}
