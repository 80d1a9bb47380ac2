/* The board model's field-width limits checked before any work (rtl_model/model_limits.h):
 * each limit refused with the scene, key or option, the value and the field named; the
 * same scenes refused by the model's own frame set-up (c5_regs_build), so the early check
 * never lets through what the model would stop later; the built-in scenes pass. */
#include <stdio.h>
#include <string.h>

#include "builtin_scenes.h"
#include "harness.h"
#include "model_limits.h"
#include "regs.h"

static c5_scene scene;

#define CAM "'camera': {'eye': [0, 0, 10], 'target': [0, 0, 0], 'up': [0, 1, 0], 'width': 8, 'height': 8}"
#define SPHERE(mat) "'surfaces': [{'type': 'sphere', 'center': [0, 0, 0], 'radius': 1, 'material': " mat "}]"
#define RAMP(dims) "'volumes': [{'generator': 'ramp', 'dims': " dims "}], " \
                   "'transfer_function': {'opacity': [[0, 0]], 'color': [[0, 1, 1, 1]]}"

static const struct {
    const char *json;
    int cells[3];
    const char *needle[3]; /* the key or option, the value and limit, the field */
} cases[] = {
    {"{" CAM ", 'render': {'max_bounces': 16}}", {1, 1, 1}, {"render.max_bounces: 16", "up to 15", "(4 bits)"}},
    {"{" CAM "}", {17, 16, 16}, {"--cells 17x16x16", "4352 cells", "cell id (12 bits)"}},
    {"{'camera': {'eye': [0, 0, 10], 'target': [0, 0, 0], 'up': [0, 1, 0], 'width': 513, 'height': 8}}",
     {1, 1, 1}, {"image 513x8", "up to 512x512", "(9+9 bits)"}},
    {"{" CAM ", " SPHERE("{'ambient': 16}") "}", {1, 1, 1}, {"surfaces[0].material.ambient", ": 16:", "UQ4.12"}},
    {"{" CAM ", " SPHERE("{'transparency': 1, 'ior': 16}") "}", {1, 1, 1},
     {"surfaces[0].material.ior: 16", "below 16", "eta UQ4.28"}},
    {"{" CAM ", " SPHERE("{'transparency': 1, 'ior': 0.0625}") "}", {1, 1, 1},
     {"surfaces[0].material.ior (as 1 / ior): 16", "below 16", "eta UQ4.28"}},
    {"{" CAM ", 'lights': [{'type': 'point', 'position': [0, 0, 5]}, {'type': 'point', 'position': [0, 0, 5],"
     " 'intensity': 20}]}", {1, 1, 1}, {"lights[1].intensity: 20", "below 16", "light_term UQ4.12"}},
    {"{" CAM ", 'render': {'background': [0, 0, 4]}}", {1, 1, 1}, {"render.background[2]: 4", "below 4", "UQ2.12"}},
    {"{" CAM ", " RAMP("[4, 4, 4]") ", 'grid': {'dims': [4, 513, 4]}}", {1, 2, 1},
     {"grid.dims", "513 voxels along axis 1 in 2 cell(s): cells of 257", "(UQ8.15 from the cell's corner)"}},
    {"{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [244, 2, 2], 'offset': [13, 0, 0]}],"
     " 'transfer_function': {'opacity': [[0, 0]], 'color': [[0, 1, 1, 1]]}}", {1, 1, 1},
     {"volumes[0] (dims + offset)", "257 voxels along axis 0", "UQ8.15"}},
    {"{" CAM ", " RAMP("[4, 4, 4]") ", 'grid': {'dims': [8001, 4, 4]}}", {32, 1, 1},
     {"grid.dims", "8001 voxels along axis 0", "geom_coord SQ13.15"}},
};

TEST(model_limits_each_named)
{
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        c5_err e;
        CHECK_MSG(c5_scene_parse(c5t_json(cases[i].json), NULL, "s.json", &scene, &e) == 0, "case %zu: %s", i, e.msg);
        CHECK_MSG(c5_model_check_scene(&scene, cases[i].cells, "s.json", &e) == -1, "case %zu accepted", i);
        CHECK_MSG(!strncmp(e.msg, "s.json: ", 8), "case %zu: \"%s\" does not name the scene", i, e.msg);
        for (int k = 0; k < 3; k++)
            CHECK_HAS(e.msg, cases[i].needle[k]);
    }
}

/* What the early check refuses, the model's own set-up refuses too (for the grid cases,
 * once the grid is built): the two lists of limits agree. */
TEST(model_limits_agree_with_the_model)
{
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        c5_err e;
        c5_supervol sv;
        CHECK(c5_scene_parse(c5t_json(cases[i].json), NULL, "s.json", &scene, &e) == 0);
        CHECK_MSG(c5_supervol_build(&scene, &sv, &e) == 0, "case %zu: %s", i, e.msg);
        CHECK_MSG(c5_model_check_grid(&scene, &sv, cases[i].cells, "s.json", &e) == -1, "case %zu: the model takes it",
                  i);
        c5_supervol_free(&sv);
    }
}

TEST(model_limits_builtin_scenes_pass)
{
    for (const c5_builtin_scene *b = c5_builtin_scenes; b->name; b++) {
        c5_err e;
        c5_supervol sv;
        const int cells[3] = {4, 4, 4};
        CHECK(c5_scene_parse(b->json, NULL, b->name, &scene, &e) == 0);
        CHECK_MSG(c5_model_check_scene(&scene, cells, b->name, &e) == 0, "%s", e.msg);
        CHECK_MSG(c5_supervol_build(&scene, &sv, &e) == 0, "%s", e.msg);
        CHECK_MSG(c5_model_check_grid(&scene, &sv, cells, b->name, &e) == 0, "%s", e.msg);
        c5_supervol_free(&sv);
    }
}
