/* The host link's packet check (common/tlp.c, docs/host-protocol.md): every rule refuses
 * what it should, with the right class (short transfer or garbage), and passes what it should. */
#include <string.h>

#include "harness.h"
#include "tlp.h"

static uint8_t p[C5_TLP_MAX_BYTES + 8];

static int check(size_t len)
{
    c5_tlp_header_t h;
    char why[160];
    return c5_tlp_check(p, len, &h, why, sizeof why);
}

TEST(tlp_accepts_each_type)
{
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_READ, 1, C5_TLP_SC, 4, 0x10)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_WRITE, 1, C5_TLP_SC, 4, 0x10)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_COMPLETION, 1, C5_TLP_SC, 4, 0x10)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_COMPLETION, 1, C5_TLP_SC, 0, 0x10)), 0); /* a write's */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_COMPLETION, 1, C5_TLP_UR, 0, 0x10)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_DMA_READ, 2, C5_TLP_SC, C5_TLP_MAX_READ, 0x300000000ull)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_DMA_COMPLETION, 2, C5_TLP_SC, C5_TLP_MAX_PAYLOAD, 8)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_DMA_COMPLETION, 2, C5_TLP_CA, 0, 8)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_DMA_WRITE, 0, C5_TLP_SC, 12, 0x200000000ull)), 0);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_INTERRUPT, 0, C5_TLP_SC, 4, 0)), 0);
    /* payload sizes: requests without data carry none */
    CHECK_INT(c5_tlp_put(p, C5_TLP_DMA_READ, 2, C5_TLP_SC, 4096, 0), C5_TLP_HEADER_BYTES);
    CHECK_INT(c5_tlp_put(p, C5_TLP_DMA_WRITE, 2, C5_TLP_SC, 4096, 0), C5_TLP_HEADER_BYTES + 4096);
}

TEST(tlp_refuses_garbage)
{
    size_t n = c5_tlp_put(p, C5_TLP_REG_READ, 1, C5_TLP_SC, 4, 0x10);
    p[3] = 0; /* sync */
    CHECK_INT(check(n), -1);
    n = c5_tlp_put(p, C5_TLP_REG_READ, 1, C5_TLP_SC, 4, 0x10);
    p[2] |= 0x08; /* a reserved bit */
    CHECK_INT(check(n), -1);
    n = c5_tlp_put(p, C5_TLP_REG_READ, 1, C5_TLP_SC, 4, 0x10);
    p[0] = 8; /* unknown type */
    CHECK_INT(check(n), -1);
    p[0] = 0;
    CHECK_INT(check(n), -1);
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_COMPLETION, 1, 2, 0, 0x10)), -1);    /* unknown status */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_READ, 1, C5_TLP_UR, 4, 0x10)), -1);  /* status in a request */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_READ, 1, C5_TLP_SC, 4, 0x12)), -1);  /* misaligned address */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_WRITE, 1, C5_TLP_SC, 8, 0x10)), -1); /* a register is 4 bytes */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_REG_READ, 1, C5_TLP_SC, 4, 1ull << 32)), -1); /* beyond 32 bits */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_INTERRUPT, 0, C5_TLP_SC, 4, 4)), -1);    /* interrupt with an address */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_DMA_READ, 1, C5_TLP_SC, 6, 0)), -1);     /* not whole dwords */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_DMA_READ, 1, C5_TLP_SC, 0, 0)), -1);     /* nothing asked */
    CHECK_INT(check(c5_tlp_put(p, C5_TLP_DMA_READ, 1, C5_TLP_SC, C5_TLP_MAX_READ + 4, 0)), -1);
    /* a transfer longer than its packet: trailing bytes are garbage, not a second packet */
    n = c5_tlp_put(p, C5_TLP_REG_WRITE, 1, C5_TLP_SC, 4, 0x10);
    CHECK_INT(check(n + 4), -1);
}

TEST(tlp_short_transfers)
{
    size_t n = c5_tlp_put(p, C5_TLP_DMA_WRITE, 1, C5_TLP_SC, 64, 0);
    CHECK_INT(check(n - 4), C5_TLP_SHORT);
    CHECK_INT(check(C5_TLP_HEADER_BYTES), C5_TLP_SHORT);
    CHECK_INT(check(C5_TLP_HEADER_BYTES - 1), C5_TLP_SHORT);
    CHECK_INT(check(0), C5_TLP_SHORT);
    CHECK_INT(check(n), 0);
}
