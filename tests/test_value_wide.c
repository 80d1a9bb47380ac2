/* The eight-lane interpolation and classification (rtl_model/proc/value_wide.h) and the voxel rows
 * of the gradient block (c5_gather_rows_at) against the scalar blocks, lane by lane, in a
 * cell copied to the RDRAM (random voxels, ghosts included) and in a grid read in place. */
#include <string.h>

#include "cells.h"
#include "harness.h"
#include "processor.h"
#include "rng.h"
#include "sample_pipe.h"
#include "shade_wide.h"
#include "value_wide.h"

static const char *scene_json =
    "{\"volumes\": [{\"generator\": \"cloud\", \"dims\": [37, 29, 23]}],"
    " \"transfer_function\": {\"opacity\": [[0, 0], [255, 1]], \"color\": [[0, 0, 0, 0], [255, 1, 1, 1]]},"
    " \"camera\": {\"eye\": [10, -50, 6], \"target\": [10, 8, 6]}}";

static int64_t uniform_i(uint64_t *st, int64_t lo, int64_t hi)
{
    return lo + (int64_t)(c5_splitmix64(st) % (uint64_t)(hi - lo + 1));
}

/* A table whose opacity is 0 on runs of entries (the samples the processor skips) and
 * anything up to 1.0 elsewhere, the largest entries included. */
static void random_table(uint64_t *st, c5_frame_regs *r)
{
    int zero = 0;
    for (int i = 0; i < 256; i++) {
        if (c5_splitmix64(st) % 16 == 0)
            zero = !zero;
        for (int c = 0; c < 3; c++)
            r->tf[i][c] = (int32_t)uniform_i(st, 0, C5_ONE15);
        r->tf[i][3] = zero ? 0 : c5_splitmix64(st) % 8 == 0 ? C5_ONE15 : (int32_t)uniform_i(st, 0, C5_ONE15);
    }
}

/* Whether c5_value_wide may refuse the sample at pos: within its margin of the grid's faces. */
static int near_face(const c5_frame_regs *r, const int64_t pos[3])
{
    for (int a = 0; a < 3; a++) {
        int64_t i = (pos[a] - (1 << (C5_POS_F - 1))) >> C5_POS_F;
        if (a == 0 ? i < 1 || i > r->dims[0] - 3 : i < 0 || i > r->dims[a] - 2)
            return 1;
    }
    return 0;
}

/* Random runs in every cell of the RDRAM: c5_value_wide's lanes are the scalar blocks' where
 * it takes the run (the colour where the opacity is not 0), and it refuses only runs that
 * come near a face. Counts into taken, refused and lit (lanes). */
static void check_runs(c5_frame_regs *r, const c5_rdram *m, uint64_t *st, int rounds, long *taken, long *refused,
                       long *lit)
{
    for (int round = 0; round < rounds; round++) {
        int64_t pos[3], S[3];
        for (int a = 0; a < 3; a++) {
            int64_t span = (int64_t)(m->hi[a] - m->lo[a]) << C5_POS_F;
            pos[a] = ((int64_t)m->lo[a] << C5_POS_F) + uniform_i(st, 0, span - 1);
            S[a] = round % 5 == 0 ? 0 : uniform_i(st, -(1 << C5_POS_F), 1 << C5_POS_F);
        }
        int n = (int)uniform_i(st, 1, C5_VALUE_LANES);
        /* the run stays in the RDRAM's cell, as the processor's runs do */
        int inside = 1;
        for (int j = 0; j < n; j++)
            for (int a = 0; a < 3; a++) {
                int64_t p = pos[a] + j * S[a];
                inside &= p >= (int64_t)m->lo[a] << C5_POS_F && p < (int64_t)m->hi[a] << C5_POS_F;
            }
        if (!inside)
            continue;
        c5_value_lanes got;
        memset(&got, 0x5a, sizeof got);
        c5_value_lanes untouched = got;
        int near = 0;
        for (int j = 0; j < n; j++) {
            int64_t p[3] = {pos[0] + j * S[0], pos[1] + j * S[1], pos[2] + j * S[2]};
            near |= near_face(r, p);
        }
        if (c5_value_wide(r, m, pos, S, n, &got) != 0) {
            CHECK_MSG(near, "round %d: a run away from the faces refused", round);
            CHECK_MSG(!memcmp(&got, &untouched, sizeof got), "round %d: a refused run wrote its lanes", round);
            (*refused)++;
            continue;
        }
        CHECK_MSG(!near, "round %d: a run near a face taken", round);
        CHECK_MSG(!(got.lit >> n), "round %d: lanes past the run lit", round);
        for (int j = 0; j < n; j++) {
            int64_t p[3] = {pos[0] + j * S[0], pos[1] + j * S[1], pos[2] + j * S[2]}, rgba[4];
            c5_corners k;
            c5_gather_values(r, m, p, &k);
            int64_t value = c5_interp_blend(k.frac, k.v);
            c5_classify_channels(r, value, 0, 4, rgba);
            CHECK_MSG(got.value[j] == value && got.alpha[j] == rgba[3], "round %d lane %d: value %d alpha %d, scalar %lld %lld",
                      round, j, got.value[j], got.alpha[j], (long long)value, (long long)rgba[3]);
            CHECK_MSG((got.lit >> j & 1) == (rgba[3] > 0), "round %d lane %d: lit", round, j);
            if (rgba[3] > 0) {
                for (int c = 0; c < 3; c++)
                    CHECK_MSG(got.rgb[c][j] == rgba[c], "round %d lane %d: channel %d %d, scalar %lld", round, j, c,
                              got.rgb[c][j], (long long)rgba[c]);
                (*lit)++;
            }
            for (int a = 0; a < 3; a++)
                CHECK_MSG(got.frac[a][j] == k.frac[a], "round %d lane %d: frac %d", round, j, a);
            CHECK_MSG(got.tag[j] == c5_cache_tag_of(p), "round %d lane %d: tag", round, j);
        }
        (*taken)++;
    }
}

/* The test grid split into cells[0] x cells[1] x cells[2], its registers and its cells. */
static void test_grid(int c0, int c1, int c2, c5_supervol *sv, c5_frame_regs *r, c5_cells *cl)
{
    c5_scene s;
    c5_err err;
    CHECK(c5_scene_parse(scene_json, NULL, "t", &s, &err) == 0 && c5_supervol_build(&s, sv, &err) == 0);
    c5_board_opts o = {.cells = {c0, c1, c2}};
    CHECK(c5_regs_build(&s, sv, &o, r, &err) == 0);
    uint8_t nz[256];
    memset(nz, 1, sizeof nz);
    CHECK(c5_cells_init(cl, sv, o.cells, nz, &err) == 0);
}

/* The cell copied to m with random voxels in place of its own, ghosts included; with ends,
 * 0 and 255 an eighth of the time each. */
static void random_cell(const c5_cells *cl, const c5_supervol *sv, int cell, c5_rdram *m, uint64_t *st, int ends)
{
    c5_err err;
    CHECK(c5_rdram_load(m, cl, sv, cell, &err) == 0);
    size_t bytes = (size_t)m->ext[0] * m->ext[1] * m->ext[2];
    for (size_t i = 0; i < bytes; i++) {
        uint64_t x = c5_splitmix64(st);
        m->v[i] = ends && x % 8 == 0 ? 255 : ends && x % 8 == 1 ? 0 : (uint8_t)(x >> 8);
    }
}

TEST(value_wide_is_the_scalar_interp_and_classify)
{
    if (!c5_shade_wide_usable()) {
        c5_value_lanes o;
        int64_t pos[3] = {1 << 16, 1 << 16, 1 << 16}, S[3] = {0, 0, 0};
        CHECK(c5_value_wide(NULL, NULL, pos, S, 1, &o) == -1); /* refused before it reads anything */
        return;
    }
    c5_supervol sv;
    static c5_frame_regs r;
    c5_cells cl;
    c5_err err;
    test_grid(2, 2, 1, &sv, &r, &cl);
    uint64_t st = 11;
    long taken = 0, refused = 0, viewed = 0, lit = 0;
    for (int cell = 0; cell < cl.count; cell++) {
        c5_rdram m = {.cell = -1};
        random_cell(&cl, &sv, cell, &m, &st, 1);
        for (int t = 0; t < 4; t++) {
            random_table(&st, &r);
            check_runs(&r, &m, &st, 3000, &taken, &refused, &lit);
        }
        c5_rdram_free(&m);
        /* the grid read in place (its own strides) */
        c5_rdram v = {.cell = -1};
        CHECK(c5_rdram_view(&v, &cl, &sv, cell, &err) == 0);
        viewed += v.view != NULL;
        random_table(&st, &r);
        check_runs(&r, &v, &st, 3000, &taken, &refused, &lit);
        c5_rdram_free(&v);
    }
    CHECK_MSG(taken > 10000 && refused > 500 && lit > 10000 && viewed == cl.count,
              "runs taken %ld, refused %ld, lit lanes %ld, cells viewed %ld", taken, refused, lit, viewed);
    c5_cells_free(&cl);
    c5_supervol_free(&sv);
}

TEST(gradient_rows_give_the_central_differences)
{
    /* c5_gather_rows_at with c5_rows_diffs against c5_gather_diffs_to at every sample of a
     * copied cell with random voxels: the same differences, and no rows where a clamp is due */
    c5_supervol sv;
    static c5_frame_regs r;
    c5_cells cl;
    test_grid(1, 2, 1, &sv, &r, &cl);
    uint64_t st = 12;
    long rows = 0, clamped = 0;
    for (int cell = 0; cell < cl.count; cell++) {
        c5_rdram m = {.cell = -1};
        random_cell(&cl, &sv, cell, &m, &st, 0);
        c5_rows_src src;
        c5_rows_src_init(&r, &m, &src);
        for (int i = 0; i < 20000; i++) {
            int64_t pos[3];
            int inner = 1;
            for (int a = 0; a < 3; a++) {
                int64_t span = (int64_t)(m.hi[a] - m.lo[a]) << C5_POS_F;
                pos[a] = ((int64_t)m.lo[a] << C5_POS_F) + uniform_i(&st, 0, span - 1);
                int64_t v = (pos[a] - (1 << (C5_POS_F - 1))) >> C5_POS_F;
                inner &= v >= 1 && v + 2 <= r.dims[a] - 1;
            }
            c5_corners k;
            c5_gather_diffs(&r, &m, pos, &k);
            uint32_t row[C5_SHADE_ROWS];
            int32_t d[3][8];
            if (!c5_gather_rows_at(&src, pos, row, 1)) {
                CHECK_MSG(!inner, "sample %d: no rows where no clamp is due", i);
                clamped++;
                continue;
            }
            CHECK_MSG(inner, "sample %d: rows where a clamp is due", i);
            c5_rows_diffs(row, 1, d);
            CHECK_MSG(!memcmp(d, k.d, sizeof d), "sample %d: the rows' differences differ", i);
            rows++;
        }
        c5_rdram_free(&m);
    }
    CHECK_MSG(rows > 20000 && clamped > 1000, "rows %ld, clamped %ld", rows, clamped);
    /* every (dy, dz) a difference uses names its own row */
    for (int k = 0; k < C5_SHADE_ROWS; k++)
        CHECK(c5_row_at(C5_ROW_DY[k], C5_ROW_DZ[k]) == k);
    c5_cells_free(&cl);
    c5_supervol_free(&sv);
}
