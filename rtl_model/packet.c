/* Ray registers <-> the 32-byte ray packet (ray.h), through the generated layout. */
#include "c5_layouts.h"
#include "ray.h"

_Static_assert(C5_RAY_PACKET_BYTES == C5_PACKET_BYTES, "the ray packet is 32 bytes");

void c5_bray_pack(const c5_bray *r, uint8_t out[C5_PACKET_BYTES])
{
    c5_ray_packet_t f = {
        .pos_x = r->pos[0], .pos_y = r->pos[1], .pos_z = r->pos[2],
        .dir_x = r->dir[0], .dir_y = r->dir[1], .dir_z = r->dir[2],
        .dest_u = r->u, .dest_v = r->v, .lifetime = r->lifetime,
        .contribution = r->w, .opacity = r->opa, .generation = r->gen,
        .cell_tree_node = r->node, .cell_id = r->cell, .type = r->type, .interaction = r->surf,
        .red = r->rgb[0], .green = r->rgb[1], .blue = r->rgb[2],
    };
    c5_ray_packet_pack(&f, out);
}

void c5_bray_unpack(const uint8_t in[C5_PACKET_BYTES], c5_bray *r)
{
    c5_ray_packet_t f;
    c5_ray_packet_unpack(in, &f);
    *r = (c5_bray){
        .pos = {f.pos_x, f.pos_y, f.pos_z}, .dir = {f.dir_x, f.dir_y, f.dir_z},
        .u = f.dest_u, .v = f.dest_v, .lifetime = f.lifetime,
        .w = f.contribution, .opa = f.opacity, .gen = f.generation,
        .node = f.cell_tree_node, .cell = f.cell_id, .type = f.type, .surf = f.interaction,
        .rgb = {f.red, f.green, f.blue},
    };
}
