/* A scene rendered with every block's taps, and its end-to-end CRCs (blocks.h). */
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "blocks.h"
#include "rng.h"

typedef struct {
    c5_vscene v;
    c5_taps blk;     /* the blocks' callbacks (ctx: &v) */
    uLong crc_packets, crc_frame;
    uint64_t packets;
} scene_run;

static void top_packet(void *ctx, const uint8_t *pk)
{
    scene_run *r = ctx;
    r->crc_packets = crc32(r->crc_packets, pk, C5_PACKET_BYTES);
    r->packets++;
    if (r->blk.packet)
        r->blk.packet(&r->v, pk);
}

static void top_queue(void *ctx, const c5_rq_in *in, const c5_rq_out *out)
{
    scene_run *r = ctx;
    if (r->blk.queue)
        r->blk.queue(&r->v, in, out);
}

static void top_tree_tag(void *ctx, uint32_t node, int cell, uint32_t result)
{
    scene_run *r = ctx;
    if (r->blk.tree_tag)
        r->blk.tree_tag(&r->v, node, cell, result);
}

static void top_frame(void *ctx, const uint64_t *fb, int w, int h)
{
    scene_run *r = ctx;
    for (size_t i = 0; i < (size_t)w * (size_t)h * 3; i++) {
        uint8_t le[8];
        for (int k = 0; k < 8; k++)
            le[k] = (uint8_t)(fb[i] >> (8 * k));
        r->crc_frame = crc32(r->crc_frame, le, 8);
    }
    if (r->blk.frame)
        r->blk.frame(&r->v, fb, w, h);
}

static void top_interp(void *ctx, const c5_corners *k, int64_t value)
{
    scene_run *r = ctx;
    if (r->blk.interp)
        r->blk.interp(&r->v, k, value);
}

static void top_gradient(void *ctx, const c5_corners *k, const int64_t gs[3], const int64_t grad[3])
{
    scene_run *r = ctx;
    if (r->blk.gradient)
        r->blk.gradient(&r->v, k, gs, grad);
}

static void top_classify(void *ctx, int64_t value, const int64_t rgba[4])
{
    scene_run *r = ctx;
    if (r->blk.classify)
        r->blk.classify(&r->v, value, rgba);
}

static void top_shade(void *ctx, const c5_shade_io *io)
{
    scene_run *r = ctx;
    if (r->blk.shade)
        r->blk.shade(&r->v, io);
}

static void top_composite(void *ctx, const c5_composite_io *io)
{
    scene_run *r = ctx;
    if (r->blk.composite)
        r->blk.composite(&r->v, io);
}

static void top_traverse(void *ctx, const c5_trav_in *in, const c5_trav_out *out)
{
    scene_run *r = ctx;
    if (r->blk.traverse)
        r->blk.traverse(&r->v, in, out);
}

static char *crc_text(uLong crc, char *buf)
{
    sprintf(buf, "crc32:%08lx", (unsigned long)crc);
    return buf;
}

json_t *c5_vec_scene(c5_vset *s, const char *name, const c5_scene *sc, const c5_supervol *sv, const int cells[3])
{
    scene_run *r = calloc(1, sizeof *r);
    c5_ctree *tree = malloc(sizeof *tree);
    c5_frame_regs *regs = malloc(sizeof *regs);
    if (!r || !tree || !regs) {
        free(r);
        free(tree);
        free(regs);
        c5_fail(s->err, "out of memory");
        return NULL;
    }
    /* The registers the board will load for the frame (the same function on the same
     * scene and split), for the blocks' configuration files. */
    c5_board_opts ro = {.cells = {cells[0] > 1 ? cells[0] : 1, cells[1] > 1 ? cells[1] : 1, cells[2] > 1 ? cells[2] : 1}};
    if (c5_supervol_empty(sv))
        ro.cells[0] = ro.cells[1] = ro.cells[2] = 1;
    if (c5_regs_build(sc, sv, &ro, regs, s->err) != 0) {
        free(r);
        free(tree);
        free(regs);
        return NULL;
    }
    r->v.regs = regs;
    c5_ctree_init(tree, 0);
    r->v.set = s;
    r->v.scene = name;
    r->v.tree = tree;
    r->v.seed = s->seed;
    for (const char *p = name; *p; p++) { /* each scene its own stream */
        r->v.seed ^= (uint64_t)(unsigned char)*p;
        c5_splitmix64(&r->v.seed);
    }
    r->blk.ctx = &r->v;
    r->crc_packets = r->crc_frame = crc32(0L, Z_NULL, 0);
    int begun = 0, rc = 0;
    while (begun < c5_n_vblock_gens) {
        const c5_vblock_gen *g = c5_vblock_gens[begun];
        if (g->tap_begin && g->tap_begin(&r->v, &r->blk) != 0) {
            rc = c5_fail(s->err, "out of memory for the %s taps", g->name);
            break;
        }
        begun++;
    }
    if (rc == 0) {
        c5_taps top = {.ctx = r,
                       .packet = top_packet,
                       .queue = top_queue,
                       .tree_tag = top_tree_tag,
                       .frame = top_frame,
                       .interp = top_interp,
                       .gradient = top_gradient,
                       .classify = top_classify,
                       .shade = top_shade,
                       .composite = top_composite,
                       .traverse = top_traverse};
        c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}, .tree = tree, .taps = &top};
        c5_image img = {0};
        c5_board_stats st;
        rc = c5_board_render(sc, sv, 0, &o, &img, &st, s->err);
        c5_image_free(&img);
    }
    /* Every block that began ends, also after an error, to free its state (the set has
     * failed then: its manifest is never written). */
    for (int i = 0; i < begun; i++)
        if (c5_vblock_gens[i]->tap_end)
            c5_vblock_gens[i]->tap_end(&r->v);
    json_t *rec = NULL;
    if (rc == 0) {
        char a[32], b[32], c[32];
        uLong ram = crc32(crc32(0L, Z_NULL, 0), tree->ram, C5_TREE_RAM_BYTES);
        rec = json_pack("{s:s, s:i, s:i, s:[i,i,i], s:s, s:s, s:I, s:s, s:i}", "scene", name, "width",
                        sc->render.width, "height", sc->render.height, "cells", cells[0], cells[1], cells[2],
                        "frame_buffer", crc_text(r->crc_frame, a), "packet_trace", crc_text(r->crc_packets, b),
                        "packets", (json_int_t)r->packets, "dsp_ram", crc_text(ram, c), "tree_slots",
                        (int)tree->used);
    }
    free(tree);
    free(regs);
    free(r);
    return rec;
}
