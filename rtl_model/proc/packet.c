/* Ray registers <-> the 32-byte ray packet (ray.h), through the generated layout. */
#include "c5_layouts.h"
#include "cells.h"
#include "ray.h"

_Static_assert(C5_RAY_PACKET_BYTES == C5_PACKET_BYTES, "the ray packet is 32 bytes");
_Static_assert(C5_RAY_PACKET_CELL_ID_WIDTH == 12 && C5_MAX_CELLS == 1 << C5_RAY_PACKET_CELL_ID_WIDTH,
               "the packet's cell id names every cell");
_Static_assert(C5_CELL_MAX_EDGE == 1 << (C5_RAY_PACKET_POS_X_WIDTH - C5_POS_F), "a cell's edge fits pos's integer bits");

/* The lower corner of `cell` in the position's raw units. */
static void corner(const c5_cells *c, uint32_t cell, int64_t k[3])
{
    int lo[3], hi[3];
    c5_cell_box(c, (int)cell, lo, hi);
    for (int a = 0; a < 3; a++)
        k[a] = (int64_t)lo[a] << C5_POS_F;
}

void c5_bray_pack(const c5_bray *r, const c5_cells *c, uint8_t out[C5_PACKET_BYTES])
{
    int64_t k[3];
    corner(c, r->cell, k);
    c5_ray_packet_t f = {
        .pos_x = r->pos[0] - k[0], .pos_y = r->pos[1] - k[1], .pos_z = r->pos[2] - k[2],
        .dir_x = r->dir[0], .dir_y = r->dir[1], .dir_z = r->dir[2],
        .dest_u = r->u, .dest_v = r->v, .lifetime = r->lifetime,
        .contribution = r->w, .opacity = r->opa, .generation = r->gen,
        .cell_tree_node = r->node, .cell_id = r->cell, .type = r->type, .interaction = r->surf,
        .red = r->rgb[0], .green = r->rgb[1], .blue = r->rgb[2],
    };
    c5_ray_packet_pack(&f, out);
}

void c5_bray_unpack(const uint8_t in[C5_PACKET_BYTES], const c5_cells *c, c5_bray *r)
{
    c5_ray_packet_t f;
    c5_ray_packet_unpack(in, &f);
    int64_t k[3];
    corner(c, f.cell_id, k);
    *r = (c5_bray){
        .pos = {f.pos_x + k[0], f.pos_y + k[1], f.pos_z + k[2]}, .dir = {f.dir_x, f.dir_y, f.dir_z},
        .u = f.dest_u, .v = f.dest_v, .lifetime = f.lifetime,
        .w = f.contribution, .opa = f.opacity, .gen = f.generation,
        .node = f.cell_tree_node, .cell = f.cell_id, .type = f.type, .surf = f.interaction,
        .rgb = {f.red, f.green, f.blue},
    };
}
