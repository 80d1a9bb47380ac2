/* The processor's per-sample datapath against cref's double arithmetic at the same exact
 * positions: the only difference allowed is the final rounding of each declared format. */
#include <math.h>
#include <string.h>

#include "cells.h"
#include "harness.h"
#include "ray.h"
#include "rng.h"
#include "sample_pipe.h"

static const char *scene_json =
    "{\"volumes\": [{\"generator\": \"blobs\", \"dims\": [21, 17, 13]}],"
    " \"transfer_function\": {\"opacity\": [[0, 0], [255, 1]], \"color\": [[0, 0, 0, 0], [255, 1, 1, 1]]},"
    " \"camera\": {\"eye\": [10, -50, 6], \"target\": [10, 8, 6]}}";

TEST(sample_pipe_interp_and_gradient_round_once)
{
    c5_scene s;
    c5_supervol sv;
    c5_err err;
    CHECK(c5_scene_parse(scene_json, NULL, "t", &s, &err) == 0 && c5_supervol_build(&s, &sv, &err) == 0);
    c5_board_opts o = {.cells = {2, 1, 1}};
    c5_frame_regs r;
    CHECK(c5_regs_build(&s, &sv, &o, &r, &err) == 0);
    uint8_t nz[256];
    for (int i = 0; i < 256; i++)
        nz[i] = 1;
    c5_cells cl;
    c5_rdram m = {.cell = -1};
    CHECK(c5_cells_init(&cl, &sv, o.cells, nz, &err) == 0);
    uint64_t rng = 5;
    for (int cell = 0; cell < cl.count; cell++) {
        CHECK(c5_rdram_load(&m, &cl, &sv, cell, &err) == 0);
        for (int i = 0; i < 20000; i++) {
            int64_t pos[3];
            for (int a = 0; a < 3; a++) { /* anywhere in the cell, edges and ghosts in use */
                int64_t span = (int64_t)(m.hi[a] - m.lo[a]) << C5_POS_F;
                pos[a] = ((int64_t)m.lo[a] << C5_POS_F) + (int64_t)(c5_splitmix64(&rng) % (uint64_t)span);
            }
            c5_sample smp;
            c5_interp(&r, &m, pos, 1, &smp);
            double v, half = ldexp(1, -9);
            c5_vec3 g;
            c5_vec3 p = v3(ldexp((double)pos[0], -C5_POS_F), ldexp((double)pos[1], -C5_POS_F),
                           ldexp((double)pos[2], -C5_POS_F)); /* spacing 1, origin 0 */
            c5_supervol_sample(&sv, p, &v, &g);
            CHECK_MSG(fabs(ldexp((double)smp.value, -8) - v) <= half, "value %g vs %g", ldexp((double)smp.value, -8), v);
            /* The datapath gradient is the blend of central differences (2 s g). */
            double gw[3] = {2 * g.x, 2 * g.y, 2 * g.z};
            for (int a = 0; a < 3; a++)
                CHECK_MSG(fabs(ldexp((double)smp.grad[a], -8) - gw[a]) <= half, "grad %d %g vs %g", a,
                          ldexp((double)smp.grad[a], -8), gw[a]);
        }
    }
    c5_rdram_free(&m);
    c5_cells_free(&cl);
    c5_supervol_free(&sv);
}

/* Classification is linear between table entries, rounded once to UQ1.15. */
TEST(sample_pipe_classify_rounds_once)
{
    c5_frame_regs r;
    memset(&r, 0, sizeof r);
    uint64_t rng = 9;
    for (int i = 0; i < 256; i++)
        for (int c = 0; c < 4; c++)
            r.tf[i][c] = (int32_t)(c5_splitmix64(&rng) % (C5_ONE15 + 1));
    for (int64_t s = 0; s <= 255 * 256; s++) {
        int64_t rgba[4];
        c5_classify(&r, s, rgba);
        int i = (int)(s >> 8) > 254 ? 254 : (int)(s >> 8);
        double f = s / 256.0 - i;
        for (int c = 0; c < 4; c++) {
            double exact = r.tf[i][c] + f * (r.tf[i + 1][c] - r.tf[i][c]);
            CHECK_MSG(fabs(rgba[c] - exact) <= 0.5, "s=%lld c=%d: %lld vs %g", (long long)s, c, (long long)rgba[c],
                      exact);
        }
    }
}

static int same_ray(const c5_bray *a, const c5_bray *b)
{
    for (int i = 0; i < 3; i++)
        if (a->pos[i] != b->pos[i] || a->dir[i] != b->dir[i] || a->rgb[i] != b->rgb[i])
            return 0;
    return a->u == b->u && a->v == b->v && a->lifetime == b->lifetime && a->w == b->w && a->opa == b->opa &&
           a->gen == b->gen && a->node == b->node && a->cell == b->cell && a->type == b->type && a->surf == b->surf;
}

/* The registers survive the 32-byte packet unchanged, at the extremes of every field, in the
 * first and the last of 4,096 cells: the packet holds the position from its cell's corner
 * (UQ8.15), the processor in grid coordinates. */
TEST(sample_pipe_packet_round_trip)
{
    static uint8_t cell_empty[C5_MAX_CELLS], block_empty[512 * 2 * 2];
    c5_cells cl;
    c5_err err;
    const int n[3] = {16, 16, 16};
    CHECK(c5_cells_init_flags(&cl, (size_t[3]){4096, 16, 16}, n, cell_empty, block_empty, &err) == 0);
    int lo[3], hi[3];
    c5_cell_box(&cl, C5_MAX_CELLS - 1, lo, hi);
    CHECK(lo[0] == 3840 && hi[0] == 4096 && lo[1] == 15 && hi[2] == 16);
    c5_bray first = {.pos = {0, 0, 0}, .dir = {-(1 << 15), -(1 << 15), -(1 << 15)}, .node = 0, .surf = 0};
    c5_bray last = {.pos = {((int64_t)hi[0] << 15) - 1, ((int64_t)hi[1] << 15) - 1, ((int64_t)hi[2] << 15) - 1},
                    .dir = {(1 << 15) - 1, (1 << 15) - 1, (1 << 15) - 1},
                    .u = 511, .v = 511, .lifetime = C5_LIFE_NONE, .w = (1 << 16) - 1, .opa = (1 << 15) - 1,
                    .gen = 15, .node = C5_NODE_NONE, .cell = C5_MAX_CELLS - 1, .type = 3, .surf = C5_SURF_NONE,
                    .rgb = {C5_RGB_MAX, C5_RGB_MAX, C5_RGB_MAX}};
    c5_bray corner = {.pos = {(int64_t)lo[0] << 15, (int64_t)lo[1] << 15, (int64_t)lo[2] << 15},
                      .cell = C5_MAX_CELLS - 1};
    const c5_bray *cases[] = {&first, &last, &corner};
    for (int i = 0; i < 3; i++) {
        uint8_t pk[C5_PACKET_BYTES];
        c5_bray back;
        c5_bray_pack(cases[i], &cl, pk);
        c5_bray_unpack(pk, &cl, &back);
        CHECK_MSG(same_ray(&back, cases[i]), "case %d", i);
        c5_ray_packet_t f;
        c5_ray_packet_unpack(pk, &f);
        for (int a = 0; a < 3; a++)
            CHECK_INT((&f.pos_x)[a], cases[i]->pos[a] - ((int64_t)(i ? lo[a] : 0) << 15));
    }
    c5_cells_free(&cl);
}
