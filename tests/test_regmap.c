/* The register map (build/gen/c5_regs_map.h, generated from spec/registers.toml): every
 * field's get/set helpers round-trip its extremes without touching the other bits, the
 * masks agree with LSB/WIDTH, fields and reserved bits tile each 32-bit word, offsets are
 * aligned, distinct and inside BAR0, and the fields' reset values assemble into each
 * register's documented reset word. Every check runs over all registers through the
 * header's X-macros, so a register added to the spec is tested without a change here. */
#include <stdint.h>
#include <string.h>

#include "c5_regs_map.h"
#include "harness.h"

typedef struct {
    const char *name;
    int lsb, width;
    uint32_t reset;
    uint32_t (*get)(uint32_t);
    uint32_t (*set)(uint32_t, uint32_t);
} fdesc;

typedef struct {
    const char *name;
    uint32_t offset, reset, reserved;
    const fdesc *fields;
    int n;
} rdesc;

#define FDESC(reg, f, lsb, w, rst) {#reg "." #f, (lsb), (w), (rst), c5_reg_##reg##_get_##f, c5_reg_##reg##_set_##f},
#define FTABLE(reg, off, rst, resv, fields) static const fdesc F_##reg[] = {fields(FDESC)};
C5_REGS(FTABLE)
#define RROW(reg, off, rst, resv, fields) \
    {#reg, (off), (rst), (resv), F_##reg, (int)(sizeof(F_##reg) / sizeof(F_##reg[0]))},
static const rdesc REGS[] = {C5_REGS(RROW)};
#define NREGS ((int)(sizeof(REGS) / sizeof(REGS[0])))

static uint32_t field_mask(const fdesc *f)
{
    uint32_t ones = f->width == 32 ? 0xFFFFFFFFu : (1u << f->width) - 1u;
    return ones << f->lsb;
}

TEST(regmap_count_and_offsets)
{
    CHECK_INT(NREGS, C5_REG_COUNT);
    for (int i = 0; i < NREGS; i++) {
        CHECK_MSG(REGS[i].offset % 4 == 0, "%s: offset 0x%x not aligned", REGS[i].name, REGS[i].offset);
        CHECK_MSG(REGS[i].offset + 4 <= C5_REG_BAR0_BYTES, "%s: beyond BAR0", REGS[i].name);
        if (i > 0)
            CHECK_MSG(REGS[i].offset > REGS[i - 1].offset, "%s: offsets not increasing", REGS[i].name);
    }
}

TEST(regmap_fields_tile_the_word)
{
    for (int i = 0; i < NREGS; i++) {
        uint32_t seen = REGS[i].reserved;
        for (int k = 0; k < REGS[i].n; k++) {
            uint32_t m = field_mask(&REGS[i].fields[k]);
            CHECK_MSG((seen & m) == 0, "%s overlaps", REGS[i].fields[k].name);
            seen |= m;
        }
        CHECK_MSG(seen == 0xFFFFFFFFu, "%s: bits 0x%08x belong to no field", REGS[i].name, ~seen);
    }
}

TEST(regmap_helpers_round_trip_extremes)
{
    static const uint32_t backgrounds[] = {0u, 0xFFFFFFFFu, 0xA5A5A5A5u, 0x5A5A5A5Au};
    for (int i = 0; i < NREGS; i++)
        for (int k = 0; k < REGS[i].n; k++) {
            const fdesc *f = &REGS[i].fields[k];
            uint32_t m = field_mask(f), max = m >> f->lsb;
            uint32_t values[] = {0u, 1u & max, max, max >> 1, max - (max >> 1)};
            for (int b = 0; b < 4; b++)
                for (int v = 0; v < 5; v++) {
                    uint32_t w = f->set(backgrounds[b], values[v]);
                    CHECK_MSG(f->get(w) == values[v], "%s: set 0x%x, got 0x%x", f->name, values[v], f->get(w));
                    CHECK_MSG((w & ~m) == (backgrounds[b] & ~m), "%s: set touched other bits", f->name);
                    CHECK_MSG((w & m) == values[v] << f->lsb, "%s: value not at its LSB", f->name);
                }
            /* get ignores every other bit */
            CHECK_MSG(f->get(~m) == 0, "%s: get sees other bits", f->name);
            CHECK_MSG(f->get(0xFFFFFFFFu) == max, "%s: get of all ones", f->name);
        }
}

TEST(regmap_reset_words_assemble)
{
    for (int i = 0; i < NREGS; i++) {
        uint32_t w = 0;
        for (int k = 0; k < REGS[i].n; k++) {
            const fdesc *f = &REGS[i].fields[k];
            CHECK_MSG(f->reset <= (field_mask(f) >> f->lsb), "%s: reset wider than its field", f->name);
            w = f->set(w, f->reset);
        }
        CHECK_MSG(w == REGS[i].reset, "%s: fields assemble 0x%08x, documented reset 0x%08x", REGS[i].name, w,
                  REGS[i].reset);
        CHECK_MSG((REGS[i].reset & REGS[i].reserved) == 0, "%s: reserved bits set at reset", REGS[i].name);
        for (int k = 0; k < REGS[i].n; k++)
            CHECK_MSG(REGS[i].fields[k].get(REGS[i].reset) == REGS[i].fields[k].reset, "%s: reset read back",
                      REGS[i].fields[k].name);
    }
}

/* A few values by hand, against docs/register-map.md, so a generator that is wrong in the
 * same way everywhere does not pass the checks above. */
TEST(regmap_known_values)
{
    CHECK_INT(C5_REG_ID_OFFSET, 0x000);
    CHECK_INT(C5_REG_ID_RESET, 0x43554235); /* "CUB5" */
    CHECK_INT(C5_REG_VERSION_RESET, 0x00010000);
    CHECK_INT(C5_REG_INT_MASK_RESET, 0x7);
    CHECK_INT(C5_REG_IMAGE_SIZE_RESET, (256u << 16) | 256u);
    CHECK_INT(c5_reg_image_size_get_height(C5_REG_IMAGE_SIZE_RESET), 256);
    CHECK_INT(C5_REG_CNT_FETCHES_OFFSET, 0x100);
    CHECK_INT(C5_REG_STATUS_ERROR_LSB, 4);
    CHECK_INT(C5_REG_STATUS_ERROR_MASK, 0xF0);
    CHECK_INT(c5_reg_status_set_error(0, 15), 0xF0);
    /* camera registers: binary64 halves; 30 degrees = 0x403E000000000000, up z 1.0 */
    CHECK_INT(C5_REG_CAM_FOV_HI_RESET, 0x403E0000u);
    CHECK_INT(C5_REG_CAM_FOV_LO_RESET, 0);
    CHECK_INT(C5_REG_CAM_UP_Z_HI_RESET, 0x3FF00000u);
    CHECK_INT(C5_REG_CAM_EYE_X_LO_OFFSET, 0x060);
    CHECK_INT(C5_REG_DMA_DOORBELL_OFFSET, 0x0D0);
    CHECK_INT(C5_REG_SCENE_ADDR_LO_OFFSET, 0x0E0);
    CHECK_INT(C5_REG_FB_ADDR_HI_OFFSET, 0x0F0);
}
