/* Scene parser tests: a full and a minimal scene, every validation rule, camera paths and
 * loading from a file. JSON in this file is written with ' for " (see c5t_json()). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "scene.h"

static c5_scene scene; /* large; kept off the stack */


static int parse(const char *json, c5_err *e)
{
    e->msg[0] = 0;
    return c5_scene_parse(c5t_json(json), "/scenes", "t.json", &scene, e);
}

/* The scene must be refused with a message "t.json: ..." holding both `where` (the JSON
 * path) and `problem`. */
#define CHECK_FAILS(json, where, problem)                                   \
    do {                                                                    \
        c5_err e_;                                                          \
        CHECK_INT(parse((json), &e_), -1);                                  \
        CHECK_MSG(!strncmp(e_.msg, "t.json: ", 8), "message \"%s\" does not start with the source", e_.msg); \
        CHECK_HAS(e_.msg, (where));                                         \
        CHECK_HAS(e_.msg, (problem));                                       \
    } while (0)

#define CAM "'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0]}"
#define TF "'transfer_function': {'opacity': [[0, 0], [255, 1]], 'color': [[0, 1, 1, 1]]}"

#define CHECK_VEC(v, X, Y, Z)          \
    do {                               \
        CHECK_NEAR((v).x, (X), 1e-12); \
        CHECK_NEAR((v).y, (Y), 1e-12); \
        CHECK_NEAR((v).z, (Z), 1e-12); \
    } while (0)

static const char FULL[] =
    "{\n"
    " 'name': 'full',\n"
    " 'grid': {'center': [1, 2, 3], 'spacing': [0.5, 1, 2], 'size': 10, 'dims': [64, 32, 16], 'fill': 7},\n"
    " 'volumes': [\n"
    "  {'file': 'data/v_64x32x16_uint16.raw', 'dims': [64, 32, 16], 'type': 'uint16', 'endian': 'big',\n"
    "   'window': [100, 4000], 'offset': [1, 2, 3]},\n"
    "  {'file': '/abs/skull_256x256x256_uint8.raw'},\n"
    "  {'generator': 'marschner_lobb', 'dims': [41, 41, 41], 'f_m': 5, 'alpha': 0.5},\n"
    "  {'generator': 'blobs', 'dims': [8, 8, 8], 'count': 20, 'seed': 99},\n"
    "  {'generator': 'cloud', 'dims': [8, 8, 8]},\n"
    "  {'generator': 'sphere', 'dims': [8, 8, 8], 'radius': 0.5},\n"
    "  {'generator': 'constant', 'dims': [1, 1, 1], 'value': 9},\n"
    "  {'generator': 'ramp', 'dims': [4, 4, 4], 'axis': 2, 'offset': [4, 0, 0]}\n"
    " ],\n"
    " 'transfer_function': {'opacity': [[0, 0], [128, 0.5], [255, 1]],\n"
    "   'color': [[0, 1, 0, 0], [255, 0, 0, 1]], 'unit_distance': 2,\n"
    "   'shading': {'ambient': 0.1, 'diffuse': 0.5, 'specular': 0.4, 'specular_power': 40}},\n"
    " 'lights': [{'type': 'point', 'position': [1, 2, 3], 'intensity': 2, 'shadows': true},\n"
    "            {'type': 'directional', 'direction': [0, 0, -2]}],\n"
    " 'surfaces': [\n"
    "  {'type': 'plane', 'point': [0, 0, -1], 'normal': [0, 0, 3], 'material': {'color': [0.2, 0.3, 0.4],\n"
    "   'ambient': 0.2, 'diffuse': 0.6, 'reflectivity': 0.5, 'transparency': 0.5, 'ior': 1.33}},\n"
    "  {'type': 'rect', 'corner': [0, 0, 0], 'u': [2, 0, 0], 'v': [0, 3, 0]},\n"
    "  {'type': 'sphere', 'center': [1, 1, 1], 'radius': 0.25}\n"
    " ],\n"
    " 'camera': {'eye': [10, 0, 0], 'target': [0, 0, 0], 'up': [0, 1, 0], 'fov': 45, 'width': 320,\n"
    "            'height': 200},\n"
    " 'camera_path': {'frames': 5, 'keys': [{'eye': [10, 0, 0], 'target': [0, 0, 0]},\n"
    "   {'eye': [0, 10, 0], 'target': [0, 0, 0], 'up': [0, 0, 1], 'fov': 60}]},\n"
    " 'render': {'step': 0.25, 'max_opacity': 0.9, 'max_bounces': 5, 'min_weight': 0.01,\n"
    "            'background': [0.1, 0.2, 0.3], 'shading': false}\n"
    "}\n";

TEST(scene_full)
{
    c5_err e;
    CHECK_MSG(parse(FULL, &e) == 0, "%s", e.msg);
    const c5_scene *s = &scene;
    CHECK(!strcmp(s->name, "full"));

    CHECK_INT(s->grid.has_center, 1);
    CHECK_VEC(s->grid.center, 1, 2, 3);
    CHECK_VEC(s->grid.spacing, 0.5, 1, 2);
    CHECK_NEAR(s->grid.size, 10, 0);
    CHECK_INT(s->grid.dims[0], 64);
    CHECK_INT(s->grid.dims[1], 32);
    CHECK_INT(s->grid.dims[2], 16);
    CHECK_INT(s->grid.fill, 7);

    CHECK_INT(s->n_volumes, 8);
    const c5_volume_desc *v = s->volumes;
    CHECK_INT(v[0].kind, C5_SRC_FILE);
    CHECK(!strcmp(v[0].path, "/scenes/data/v_64x32x16_uint16.raw"));
    CHECK_INT(v[0].raw.dims[0], 64);
    CHECK_INT(v[0].raw.dims[2], 16);
    CHECK_INT(v[0].raw.type, C5_VOX_U16);
    CHECK_INT(v[0].raw.big_endian, 1);
    CHECK_INT(v[0].has_window, 1);
    CHECK_NEAR(v[0].window[0], 100, 0);
    CHECK_NEAR(v[0].window[1], 4000, 0);
    CHECK_INT(v[0].offset[0], 1);
    CHECK_INT(v[0].offset[2], 3);
    CHECK(!strcmp(v[1].path, "/abs/skull_256x256x256_uint8.raw"));
    CHECK_INT(v[1].raw.type, C5_VOX_NONE);
    CHECK_INT(v[1].raw.dims[0], 0);
    CHECK_INT(v[1].raw.big_endian, 0);
    CHECK_INT(v[1].has_window, 0);
    CHECK_INT(v[1].offset[0], 0);
    CHECK_INT(v[2].kind, C5_SRC_GENERATOR);
    CHECK_INT(v[2].generator, C5_GEN_MARSCHNER_LOBB);
    CHECK_INT(v[2].gen_dims[1], 41);
    CHECK_NEAR(v[2].f_m, 5, 0);
    CHECK_NEAR(v[2].alpha, 0.5, 0);
    CHECK_INT(v[3].generator, C5_GEN_BLOBS);
    CHECK_INT(v[3].count, 20);
    CHECK_INT(v[3].seed, 99);
    CHECK_INT(v[4].generator, C5_GEN_CLOUD);
    CHECK_INT(v[4].seed, 1);
    CHECK_INT(v[5].generator, C5_GEN_SPHERE);
    CHECK_NEAR(v[5].radius, 0.5, 0);
    CHECK_NEAR(v[5].value, 200, 0);
    CHECK_INT(v[6].generator, C5_GEN_CONSTANT);
    CHECK_NEAR(v[6].value, 9, 0);
    CHECK_INT(v[7].generator, C5_GEN_RAMP);
    CHECK_INT(v[7].axis, 2);
    CHECK_INT(v[7].offset[0], 4);

    CHECK_INT(s->tf.n_opacity, 3);
    CHECK_NEAR(s->tf.opacity[1][0], 128, 0);
    CHECK_NEAR(s->tf.opacity[1][1], 0.5, 0);
    CHECK_INT(s->tf.n_color, 2);
    CHECK_NEAR(s->tf.color[1][0], 255, 0);
    CHECK_NEAR(s->tf.color[1][3], 1, 0);
    CHECK_NEAR(s->tf.color[0][1], 1, 0);
    CHECK_NEAR(s->tf.unit_distance, 2, 0);
    CHECK_NEAR(s->tf.ambient, 0.1, 0);
    CHECK_NEAR(s->tf.diffuse, 0.5, 0);
    CHECK_NEAR(s->tf.specular, 0.4, 0);
    CHECK_NEAR(s->tf.specular_power, 40, 0);

    CHECK_INT(s->n_lights, 2);
    CHECK_INT(s->lights[0].kind, C5_LIGHT_POINT);
    CHECK_VEC(s->lights[0].position, 1, 2, 3);
    CHECK_NEAR(s->lights[0].intensity, 2, 0);
    CHECK_INT(s->lights[0].shadows, 1);
    CHECK_INT(s->lights[1].kind, C5_LIGHT_DIRECTIONAL);
    CHECK_VEC(s->lights[1].direction, 0, 0, -1); /* normalised */
    CHECK_NEAR(s->lights[1].intensity, 1, 0);    /* defaults */
    CHECK_INT(s->lights[1].shadows, 0);

    CHECK_INT(s->n_surfaces, 3);
    const c5_surface *f = s->surfaces;
    CHECK_INT(f[0].kind, C5_SURF_PLANE);
    CHECK_VEC(f[0].point, 0, 0, -1);
    CHECK_VEC(f[0].normal, 0, 0, 1);
    CHECK_VEC(f[0].mat.color, 0.2, 0.3, 0.4);
    CHECK_NEAR(f[0].mat.ambient, 0.2, 0);
    CHECK_NEAR(f[0].mat.diffuse, 0.6, 0);
    CHECK_NEAR(f[0].mat.reflectivity, 0.5, 0);
    CHECK_NEAR(f[0].mat.transparency, 0.5, 0);
    CHECK_NEAR(f[0].mat.ior, 1.33, 0);
    CHECK_INT(f[1].kind, C5_SURF_RECT);
    CHECK_VEC(f[1].u, 2, 0, 0);
    CHECK_VEC(f[1].v, 0, 3, 0);
    CHECK_VEC(f[1].normal, 0, 0, 1); /* normalize(u x v) */
    CHECK_VEC(f[1].mat.color, 0.8, 0.8, 0.8); /* material defaults */
    CHECK_NEAR(f[1].mat.ambient, 0.1, 0);
    CHECK_NEAR(f[1].mat.diffuse, 0.9, 0);
    CHECK_NEAR(f[1].mat.reflectivity, 0, 0);
    CHECK_NEAR(f[1].mat.transparency, 0, 0);
    CHECK_NEAR(f[1].mat.ior, 1.5, 0);
    CHECK_INT(f[2].kind, C5_SURF_SPHERE);
    CHECK_VEC(f[2].point, 1, 1, 1);
    CHECK_NEAR(f[2].radius, 0.25, 0);

    CHECK_VEC(s->camera.eye, 10, 0, 0);
    CHECK_VEC(s->camera.up, 0, 1, 0);
    CHECK_NEAR(s->camera.fov_deg, 45, 0);
    CHECK_INT(s->render.width, 320);
    CHECK_INT(s->render.height, 200);
    CHECK_INT(s->path.n_keys, 2);
    CHECK_INT(s->path.frames, 5);
    CHECK_INT(c5_scene_frames(s), 5);
    CHECK_VEC(s->path.keys[0].up, 0, 1, 0);        /* from the camera */
    CHECK_NEAR(s->path.keys[0].fov_deg, 45, 0);    /* from the camera */
    CHECK_VEC(s->path.keys[1].up, 0, 0, 1);
    CHECK_NEAR(s->path.keys[1].fov_deg, 60, 0);

    CHECK_NEAR(s->render.step, 0.25, 0);
    CHECK_NEAR(s->render.max_opacity, 0.9, 0);
    CHECK_INT(s->render.max_bounces, 5);
    CHECK_NEAR(s->render.min_weight, 0.01, 0);
    CHECK_VEC(s->render.background, 0.1, 0.2, 0.3);
    CHECK_INT(s->render.shading, 0);
}

TEST(scene_minimal_defaults)
{
    c5_err e;
    CHECK_MSG(parse("{" CAM "}", &e) == 0, "%s", e.msg);
    const c5_scene *s = &scene;
    CHECK(!strcmp(s->name, "t")); /* from "t.json" */
    CHECK_INT(s->grid.has_center, 0);
    CHECK_VEC(s->grid.origin, 0, 0, 0);
    CHECK_VEC(s->grid.spacing, 1, 1, 1);
    CHECK_NEAR(s->grid.size, 0, 0);
    CHECK_INT(s->grid.dims[0], 0);
    CHECK_INT(s->grid.fill, 0);
    CHECK_INT(s->n_volumes, 0);
    CHECK_INT(s->tf.n_opacity, 0);
    CHECK_NEAR(s->tf.unit_distance, 0, 0);
    CHECK_NEAR(s->tf.ambient, 0.3, 0);
    CHECK_NEAR(s->tf.diffuse, 0.7, 0);
    CHECK_NEAR(s->tf.specular, 0.2, 0);
    CHECK_NEAR(s->tf.specular_power, 20, 0);
    CHECK_INT(s->n_lights, 0);
    CHECK_INT(s->n_surfaces, 0);
    CHECK_VEC(s->camera.eye, 5, 0, 0);
    CHECK_VEC(s->camera.target, 0, 0, 0);
    CHECK_VEC(s->camera.up, 0, 0, 1);
    CHECK_NEAR(s->camera.fov_deg, 30, 0);
    CHECK_INT(s->render.width, 256);
    CHECK_INT(s->render.height, 256);
    CHECK_INT(s->path.n_keys, 0);
    CHECK_INT(c5_scene_frames(s), 1);
    CHECK_NEAR(s->render.step, 0, 0);
    CHECK_NEAR(s->render.max_opacity, 0.99, 0);
    CHECK_INT(s->render.max_bounces, 3);
    CHECK_NEAR(s->render.min_weight, 1.0 / 256, 0);
    CHECK_VEC(s->render.background, 0, 0, 0);
    CHECK_INT(s->render.shading, 1);
    c5_camera c = c5_scene_camera_at(s, 0);
    CHECK_VEC(c.eye, 5, 0, 0);
    CHECK_NEAR(c.fov_deg, 30, 0);

    /* Generator defaults, shading-section defaults, the built-in name. */
    CHECK_MSG(c5_scene_parse(c5t_json("{" CAM ", 'volumes': [{'generator': 'marschner_lobb', 'dims': [4, 4, 4]},"
                               "{'generator': 'blobs', 'dims': [4, 4, 4]}, {'generator': 'sphere', 'dims': [4, 4, 4]},"
                               "{'generator': 'constant', 'dims': [4, 4, 4]}, {'generator': 'ramp', 'dims': [4, 4, 4]}],"
                               TF ", 'grid': {'origin': [1, 2, 3]}, 'render': {}}"),
                             NULL, "built-in scene demo", &scene, &e) == 0, "%s", e.msg);
    CHECK(!strcmp(s->name, "demo"));
    CHECK_VEC(s->grid.origin, 1, 2, 3);
    CHECK_NEAR(s->volumes[0].f_m, 6, 0);
    CHECK_NEAR(s->volumes[0].alpha, 0.25, 0);
    CHECK_INT(s->volumes[1].count, 12);
    CHECK_INT(s->volumes[1].seed, 1);
    CHECK_NEAR(s->volumes[2].radius, 0.4, 0);
    CHECK_NEAR(s->volumes[2].value, 200, 0);
    CHECK_NEAR(s->volumes[3].value, 0, 0);
    CHECK_INT(s->volumes[4].axis, 0);
    CHECK_NEAR(s->tf.specular_power, 20, 0);
    CHECK_NEAR(s->render.max_opacity, 0.99, 0);
}

TEST(scene_error_leaves_output_unchanged)
{
    c5_err e;
    snprintf(scene.name, sizeof scene.name, "keep");
    CHECK_INT(parse("{'camera': {'eye': [5, 0, 0]}}", &e), -1);
    CHECK(!strcmp(scene.name, "keep"));
}

TEST(scene_malformed_json)
{
    CHECK_FAILS("{" CAM ",\n 'render': {'step': 1,, }}", "line 2, column", "");
    CHECK_FAILS("{" CAM "} trailing", "line 1, column", "end of file expected");
    CHECK_FAILS("", "line 1, column", "expected");
    CHECK_FAILS("[1, 2]", "top level", "got an array");
}

TEST(scene_missing_keys)
{
    CHECK_FAILS("{}", "camera", "missing required key");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0]}}", "camera.target", "missing required key");
    CHECK_FAILS("{'camera': {'target': [5, 0, 0]}}", "camera.eye", "missing required key");
    CHECK_FAILS("{" CAM ", 'lights': [{'position': [0, 0, 0]}]}", "lights[0].type", "missing required key");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'point'}]}", "lights[0].position", "missing required key");
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'sphere', 'center': [0, 0, 0]}]}", "surfaces[0].radius",
                "missing required key");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [2, 2, 2]}]}", "transfer_function",
                "missing required key");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp'}], " TF "}", "volumes[0].dims", "missing required key");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1]]}}", "transfer_function.color",
                "missing required key");
    CHECK_FAILS("{" CAM ", 'camera_path': {'keys': []}}", "camera_path.frames", "missing required key");
    CHECK_FAILS("{" CAM ", 'camera_path': {'frames': 2, 'keys': [{'eye': [1, 0, 0], 'target': [0, 0, 0]},"
                "{'eye': [1, 0, 0]}]}}", "camera_path.keys[1].target", "missing required key");
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': 'a.raw', 'dims': [2, 2, 2]}], " TF "}", "volumes[0].type",
                "missing required key");
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': 'a.raw', 'type': 'uint8'}], " TF "}", "volumes[0].dims",
                "missing required key");
}

TEST(scene_wrong_types)
{
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'fov': '30'}}", "camera.fov",
                "expected a number, got a string");
    CHECK_FAILS("{'camera': {'eye': [5, 0], 'target': [0, 0, 0]}}", "camera.eye",
                "expected an array of 3 numbers, got 2 elements");
    CHECK_FAILS("{'camera': {'eye': 5, 'target': [0, 0, 0]}}", "camera.eye",
                "expected an array of 3 numbers, got a number");
    CHECK_FAILS("{'camera': {'eye': [5, null, 0], 'target': [0, 0, 0]}}", "camera.eye[1]",
                "expected a number, got null");
    CHECK_FAILS("{'camera': []}", "camera", "expected an object, got an array");
    CHECK_FAILS("{" CAM ", 'name': 7}", "name", "expected a string, got a number");
    CHECK_FAILS("{" CAM ", 'lights': {}}", "lights", "expected an array, got an object");
    CHECK_FAILS("{" CAM ", 'lights': [[]]}", "lights[0]", "expected an object, got an array");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'point', 'position': [0, 0, 0], 'shadows': 1}]}",
                "lights[0].shadows", "expected true or false, got a number");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'spot'}]}", "lights[0].type",
                "must be one of \"point\", \"directional\", got \"spot\"");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1, 2]], 'color': [[0, 1, 1, 1]]}}",
                "transfer_function.opacity[0]", "expected an array of 2 numbers, got 3 elements");
    CHECK_FAILS("{" CAM ", 'render': {'shading': 'yes'}}", "render.shading", "expected true or false");
}

TEST(scene_nan_infinity)
{
    CHECK_FAILS("{'camera': {'eye': [NaN, 0, 0], 'target': [0, 0, 0]}}", "line 1, column", "invalid token");
    CHECK_FAILS("{'camera': {'eye': [Infinity, 0, 0], 'target': [0, 0, 0]}}", "line 1, column", "invalid token");
    CHECK_FAILS("{'camera': {'eye': [-Infinity, 0, 0], 'target': [0, 0, 0]}}", "line 1, column", "invalid token");
}

TEST(scene_number_overflow)
{
    CHECK_FAILS("{'camera': {'eye': [1e999, 0, 0], 'target': [0, 0, 0]}}", "line 1, column", "overflow");
    CHECK_FAILS("{" CAM ", 'render': {'max_bounces': 99999999999999999999999}}", "line 1, column", "too big");
}

TEST(scene_negative_sizes)
{
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [-1, 4, 4]}], " TF "}", "volumes[0].dims[0]",
                "must be in [1, 65535], got -1");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [4, 0, 4]}], " TF "}", "volumes[0].dims[1]",
                "must be in [1, 65535], got 0");
    CHECK_FAILS("{" CAM ", 'grid': {'dims': [70000, 1, 1]}}", "grid.dims[0]", "must be in [1, 65535], got 70000");
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'sphere', 'center': [0, 0, 0], 'radius': -1}]}",
                "surfaces[0].radius", "must be in [1e-06, 1000000], got -1");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'width': -5}}", "camera.width",
                "must be in [1, 4096], got -5");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'height': 5000}}", "camera.height",
                "must be in [1, 4096], got 5000");
    CHECK_FAILS("{" CAM ", 'grid': {'spacing': [1, 0, 1]}}", "grid.spacing[1]", "must be in [1e-06, 1000000], got 0");
    CHECK_FAILS("{" CAM ", 'grid': {'size': -2}}", "grid.size", "must be in [1e-06, 1000000], got -2");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'sphere', 'dims': [4, 4, 4], 'radius': 1.5}], " TF "}",
                "volumes[0].radius", "must be in (0, 1], got 1.5");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [4, 4, 4], 'offset': [0, -1, 0]}], " TF "}",
                "volumes[0].offset[1]", "got -1");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'point', 'position': [0, 0, 0], 'intensity': -1}]}",
                "lights[0].intensity", "must be in [0, 1000], got -1");
}

TEST(scene_zero_vectors)
{
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'plane', 'point': [0, 0, 0], 'normal': [0, 0, 0]}]}",
                "surfaces[0].normal", "must have a length of at least 1e-06 (shorter counts as zero), got [0, 0, 0]");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'directional', 'direction': [0, 0, 0]}]}", "lights[0].direction",
                "must have a length of at least 1e-06");
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'rect', 'corner': [0, 0, 0], 'u': [0, 0, 0], 'v': [0, 1, 0]}]}",
                "surfaces[0].u", "must have a length of at least 1e-06");
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'rect', 'corner': [0, 0, 0], 'u': [1, 0, 0], 'v': [1, 1, 0]}]}",
                "surfaces[0].v", "must be perpendicular to u");
}

TEST(scene_fov_bounds)
{
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'fov': 0}}", "camera.fov",
                "must be in (0, 180), got 0");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'fov': 180}}", "camera.fov",
                "must be in (0, 180), got 180");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'fov': 190}}", "camera.fov",
                "must be in (0, 180), got 190");
    c5_err e;
    CHECK_MSG(parse("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'fov': 179.5}}", &e) == 0, "%s", e.msg);
}

TEST(scene_unknown_keys)
{
    CHECK_FAILS("{" CAM ", 'foo': 1}", "t.json: foo", "unknown key");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'foo': 1}}", "camera.foo", "unknown key");
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'sphere', 'center': [0, 0, 0], 'radius': 1},"
                "{'type': 'sphere', 'center': [0, 0, 0], 'radius': 1, 'material': {'shine': 1}}]}",
                "surfaces[1].material.shine", "unknown key");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1]], 'color': [[0, 1, 1, 1]],"
                "'shading': {'gloss': 1}}}", "transfer_function.shading.gloss", "unknown key");
    CHECK_FAILS("{" CAM ", 'camera_path': {'frames': 2, 'keys': [{'eye': [1, 0, 0], 'target': [0, 0, 0]},"
                "{'eye': [2, 0, 0], 'target': [0, 0, 0], 'width': 5}]}}", "camera_path.keys[1].width", "unknown key");
    CHECK_FAILS("{" CAM ", 'grid': {'origin': [0, 0, 0], 'Spacing': [1, 1, 1]}}", "grid.Spacing", "unknown key");
    CHECK_FAILS("{" CAM ", 'render': {'samples': 4}}", "render.samples", "unknown key");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [2, 2, 2], 'scale': 2}], " TF "}",
                "volumes[0].scale", "unknown key");
}

TEST(scene_duplicate_key)
{
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0],\n 'fov': 30, 'fov': 40}}", "line 2, column",
                "duplicate object key");
}

TEST(scene_tf_rules)
{
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 0], [128, 1], [100, 1]], 'color': [[0, 1, 1, 1]]}}",
                "transfer_function.opacity[2]", "x must rise strictly, got 100 after 128");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1]], 'color': [[5, 1, 1, 1], [5, 0, 0, 0]]}}",
                "transfer_function.color[1]", "x must rise strictly, got 5 after 5");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1.5]], 'color': [[0, 1, 1, 1]]}}",
                "transfer_function.opacity[0][1]", "must be in [0, 1], got 1.5");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[256, 1]], 'color': [[0, 1, 1, 1]]}}",
                "transfer_function.opacity[0][0]", "must be in [0, 255], got 256");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [], 'color': [[0, 1, 1, 1]]}}",
                "transfer_function.opacity", "needs at least 1 entry, got 0");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1]], 'color': [[0, 1, 1, 1]], 'unit_distance': 0}}",
                "transfer_function.unit_distance", "must be in [1e-06, 1000000], got 0");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1]], 'color': [[0, 1, 1, 1]],"
                "'shading': {'specular_power': 0.5}}}", "transfer_function.shading.specular_power",
                "must be in [1, 10000], got 0.5");
}

TEST(scene_reflectivity_plus_transparency)
{
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'sphere', 'center': [0, 0, 0], 'radius': 1,"
                "'material': {'reflectivity': 0.6, 'transparency': 0.5}}]}",
                "surfaces[0].material", "reflectivity + transparency must be <= 1, got 0.6 + 0.5");
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'sphere', 'center': [0, 0, 0], 'radius': 1,"
                "'material': {'color': [1, 1.2, 1]}}]}", "surfaces[0].material.color[1]", "must be in [0, 1], got 1.2");
}

TEST(scene_volume_source_rules)
{
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': 'a.raw', 'generator': 'ramp', 'dims': [2, 2, 2]}], " TF "}",
                "volumes[0]", "has both \"file\" and \"generator\"");
    CHECK_FAILS("{" CAM ", 'volumes': [{'dims': [2, 2, 2]}], " TF "}", "volumes[0]",
                "needs either \"file\" or \"generator\"");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'blobs', 'dims': [2, 2, 2], 'radius': 0.5}], " TF "}",
                "volumes[0].radius", "not allowed for generator \"blobs\"");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'cloud', 'dims': [2, 2, 2], 'count': 3}], " TF "}",
                "volumes[0].count", "not allowed for generator \"cloud\"");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [2, 2, 2], 'type': 'uint8'}], " TF "}",
                "volumes[0].type", "not allowed for generator \"ramp\"");
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': 'a.raw', 'seed': 3}], " TF "}", "volumes[0].seed",
                "not allowed for file volumes");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'perlin', 'dims': [2, 2, 2]}], " TF "}",
                "volumes[0].generator", "must be one of \"marschner_lobb\"");
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': 'a.raw', 'window': [10, 10]}], " TF "}", "volumes[0].window",
                "must have lo < hi, got [10, 10]");
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': 'a.raw', 'dims': [2, 2, 2], 'type': 'uint8', 'window': [0, 9]}], "
                TF "}", "volumes[0].window", "only for uint16 volumes");
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': 'a.raw', 'endian': 'middle'}], " TF "}", "volumes[0].endian",
                "must be one of \"little\", \"big\", got \"middle\"");
    CHECK_FAILS("{" CAM ", 'volumes': [{'file': ''}], " TF "}", "volumes[0].file", "must not be empty");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'directional', 'direction': [0, 0, 1], 'position': [0, 0, 0]}]}",
                "lights[0].position", "not allowed for directional lights");
    CHECK_FAILS("{" CAM ", 'surfaces': [{'type': 'plane', 'point': [0, 0, 0], 'normal': [0, 0, 1], 'radius': 1}]}",
                "surfaces[0].radius", "not allowed for plane surfaces");
}

TEST(scene_array_limits)
{
    char json[4096] = "{" CAM ", 'transfer_function': {'opacity': [[0, 1]], 'color': [[0, 1, 1, 1]]}, 'volumes': [";
    for (int i = 0; i <= C5_MAX_VOLUMES; i++)
        strcat(json, i ? ", {'generator': 'constant', 'dims': [1, 1, 1]}" : "{'generator': 'constant', 'dims': [1, 1, 1]}");
    strcat(json, "]}");
    CHECK_FAILS(json, "volumes", "at most 8 entries, got 9");
    CHECK_FAILS("{" CAM ", 'camera_path': {'frames': 2, 'keys': [{'eye': [1, 0, 0], 'target': [0, 0, 0]}]}}",
                "camera_path.keys", "needs at least 2 entries, got 1");
    CHECK_FAILS("{" CAM ", 'camera_path': {'frames': 0, 'keys': []}}", "camera_path.frames",
                "must be in [1, 10000], got 0");
}

TEST(scene_real_for_integer)
{
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'width': 2.5}}", "camera.width",
                "expected an integer, got 2.5");
    CHECK_FAILS("{" CAM ", 'volumes': [{'generator': 'ramp', 'dims': [8, 8.5, 8]}], " TF "}", "volumes[0].dims[1]",
                "expected an integer, got 8.5");
    CHECK_FAILS("{" CAM ", 'render': {'max_bounces': 2.0}}", "render.max_bounces", "expected an integer, got 2");
    CHECK_FAILS("{" CAM ", 'grid': {'fill': 'a'}}", "grid.fill", "expected an integer, got a string");
    CHECK_FAILS("{" CAM ", 'render': {'max_bounces': 17}}", "render.max_bounces", "must be in [0, 16], got 17");
}

TEST(scene_camera_geometry)
{
    CHECK_FAILS("{'camera': {'eye': [0, 0, 5], 'target': [0, 0, 0]}}", "camera.up",
                "must not be parallel to target - eye");
    CHECK_FAILS("{'camera': {'eye': [1, 1, 1], 'target': [2, 2, 2], 'up': [-3, -3, -3]}}", "camera.up",
                "parallel");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'up': [0, 0, 0]}}", "camera.up", "zero");
    CHECK_FAILS("{'camera': {'eye': [1, 2, 3], 'target': [1, 2, 3]}}", "camera.target",
                "must be at least 1e-06 from eye, got [1, 2, 3]");
    CHECK_FAILS("{" CAM ", 'camera_path': {'frames': 2, 'keys': [{'eye': [1, 0, 0], 'target': [0, 0, 0]},"
                "{'eye': [0, 0, 1], 'target': [0, 0, 0]}]}}", "camera_path.keys[1].up", "parallel");
}

TEST(scene_camera_path_interpolation)
{
    c5_err e;
    CHECK_MSG(parse("{'camera': {'eye': [9, 9, 9], 'target': [0, 0, 0], 'fov': 50},"
                    " 'camera_path': {'frames': 5, 'keys': ["
                    "  {'eye': [0.1, 0, 0], 'target': [0, 1, 0], 'up': [0, 0, 1], 'fov': 20},"
                    "  {'eye': [1, 2, 3], 'target': [0, 0, 0], 'up': [0, 1, 0], 'fov': 40},"
                    "  {'eye': [0.3, 4, 10], 'target': [0, 0, 1], 'up': [1, 0, 0], 'fov': 100}]}}",
                    &e) == 0,
              "%s", e.msg);
    CHECK_INT(c5_scene_frames(&scene), 5);
    c5_camera c = c5_scene_camera_at(&scene, 0); /* frame 0: key 0 exactly */
    CHECK(c.eye.x == 0.1 && c.eye.y == 0 && c.eye.z == 0);
    CHECK_VEC(c.target, 0, 1, 0);
    CHECK(c.fov_deg == 20);
    c = c5_scene_camera_at(&scene, 4); /* last frame: last key exactly */
    CHECK(c.eye.x == 0.3 && c.eye.y == 4 && c.eye.z == 10);
    CHECK(c.target.z == 1);
    CHECK(c.up.x == 1 && c.up.y == 0);
    CHECK(c.fov_deg == 100);
    c = c5_scene_camera_at(&scene, 2); /* t = 1: key 1 */
    CHECK_VEC(c.eye, 1, 2, 3);
    CHECK_NEAR(c.fov_deg, 40, 1e-12);
    c = c5_scene_camera_at(&scene, 1); /* t = 0.5: halfway between keys 0 and 1 */
    CHECK_VEC(c.eye, 0.55, 1, 1.5);
    CHECK_VEC(c.target, 0, 0.5, 0);
    CHECK_VEC(c.up, 0, 0.5, 0.5);
    CHECK_NEAR(c.fov_deg, 30, 1e-12);
    c = c5_scene_camera_at(&scene, 3); /* t = 1.5: halfway between keys 1 and 2 */
    CHECK_VEC(c.eye, 0.65, 3, 6.5);
    CHECK_NEAR(c.fov_deg, 70, 1e-12);

    /* Two keys over three frames: the middle frame is exactly halfway. */
    CHECK_MSG(parse("{" CAM ", 'camera_path': {'frames': 3, 'keys': [{'eye': [2, 0, 0], 'target': [0, 0, 0]},"
                    "{'eye': [4, 2, 0], 'target': [0, 0, 0], 'fov': 60}]}}", &e) == 0, "%s", e.msg);
    c = c5_scene_camera_at(&scene, 1);
    CHECK_VEC(c.eye, 3, 1, 0);
    CHECK_NEAR(c.fov_deg, 45, 1e-12); /* key 0 took the camera's default 30 */

    /* One frame: the first key. */
    CHECK_MSG(parse("{" CAM ", 'camera_path': {'frames': 1, 'keys': [{'eye': [2, 0, 0], 'target': [0, 0, 0]},"
                    "{'eye': [4, 2, 0], 'target': [0, 0, 0]}]}}", &e) == 0, "%s", e.msg);
    CHECK_INT(c5_scene_frames(&scene), 1);
    c = c5_scene_camera_at(&scene, 0);
    CHECK_VEC(c.eye, 2, 0, 0);
}

static int write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    fputs(text, f);
    return fclose(f);
}

TEST(scene_load_file)
{
    c5_err e;
    const char *path = c5t_path(0, "my.scene.json");
    CHECK_INT(write_file(path, c5t_json("{" CAM ", 'volumes': [{'file': 'vol_2x2x2_uint8.raw'}], " TF "}")), 0);
    CHECK_MSG(c5_scene_load_file(path, &scene, &e) == 0, "%s", e.msg);
    CHECK(!strcmp(scene.name, "my.scene"));
    char want[1100];
    snprintf(want, sizeof want, "%s/vol_2x2x2_uint8.raw", c5t_tmpdir());
    CHECK_MSG(!strcmp(scene.volumes[0].path, want), "path %s, want %s", scene.volumes[0].path, want);

    /* Errors name the file. */
    CHECK_INT(write_file(path, c5t_json("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'fov': 0}}")), 0);
    CHECK_INT(c5_scene_load_file(path, &scene, &e), -1);
    CHECK_HAS(e.msg, path);
    CHECK_HAS(e.msg, "camera.fov: must be in (0, 180), got 0");
}

TEST(scene_load_file_missing)
{
    c5_err e;
    const char *path = c5t_path(0, "absent.json");
    CHECK_INT(c5_scene_load_file(path, &scene, &e), -1);
    CHECK_HAS(e.msg, path);
    CHECK_HAS(e.msg, "cannot open: No such file or directory");
}

TEST(scene_load_file_too_big)
{
    c5_err e;
    const char *path = c5t_path(0, "big.json");
    FILE *f = fopen(path, "wb");
    CHECK(f);
    CHECK(fseek(f, (16L << 20), SEEK_SET) == 0); /* 16 MiB + 1 bytes */
    fputc(' ', f);
    CHECK_INT(fclose(f), 0);
    CHECK_INT(c5_scene_load_file(path, &scene, &e), -1);
    CHECK_HAS(e.msg, path);
    CHECK_HAS(e.msg, "16 MiB");
}

/* Every number has a range (docs/scene-format.md, "Valid ranges"); the values that made
 * cref hang or write +Inf are refused at parse time, and the message prints them with %g,
 * not 300 digits. */
TEST(scene_valid_ranges)
{
#define SPHERE(mat) "'surfaces': [{'type': 'sphere', 'center': [0, 0, 0], 'radius': 1, 'material': " mat "}]"
    CHECK_FAILS("{" CAM ", " SPHERE("{'transparency': 1, 'ior': 1e16}") "}", "surfaces[0].material.ior",
                "must be in [0.001, 1000], got 1e+16");
    CHECK_FAILS("{" CAM ", " SPHERE("{'transparency': 1, 'ior': 1e300}") "}", "surfaces[0].material.ior",
                "got 1e+300");
    CHECK_FAILS("{" CAM ", " SPHERE("{'ambient': 1e300}") "}", "surfaces[0].material.ambient",
                "must be in [0, 1000], got 1e+300");
    CHECK_FAILS("{" CAM ", 'render': {'step': 1e-12}}", "render.step", "must be in [1e-06, 1000000], got 1e-12");
    CHECK_FAILS("{" CAM ", 'grid': {'spacing': [1e-30, 1, 1]}}", "grid.spacing[0]", "got 1e-30");
    CHECK_FAILS("{" CAM ", 'render': {'background': [0, 1e300, 0]}}", "render.background[1]",
                "must be in [0, 1000], got 1e+300");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'point', 'position': [0, 0, 9], 'intensity': 1e300}]}",
                "lights[0].intensity", "must be in [0, 1000], got 1e+300");
    CHECK_FAILS("{" CAM ", 'transfer_function': {'opacity': [[0, 1]], 'color': [[0, 1, 1, 1]],"
                " 'shading': {'ambient': 1e300}}}", "transfer_function.shading.ambient", "got 1e+300");
    CHECK_FAILS("{'camera': {'eye': [1e300, 0, 0], 'target': [0, 0, 0]}}", "camera.eye[0]",
                "must be in [-1000000, 1000000], got 1e+300");
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'point', 'position': [0, -2e6, 0]}]}", "lights[0].position[1]",
                "got -2000000");
    /* The ends of each range are accepted. */
    c5_err e;
    CHECK_MSG(parse("{'camera': {'eye': [1e6, 0, 0], 'target': [-1e6, 0, 0]}, 'render': {'step': 1e-6,"
                    " 'background': [1000, 0, 0]}, 'lights': [{'type': 'point', 'position': [0, 0, 1e6],"
                    " 'intensity': 1000}], " SPHERE("{'transparency': 1, 'ior': 1000, 'ambient': 1000}") "}",
                    &e) == 0,
              "%s", e.msg);
#undef SPHERE
}

/* A direction is zero when its length is below 1e-6 (computed without underflow): the
 * message gives the length instead of calling [1e-300, 0, -1e-300] "zero"; a short but
 * valid direction is normalised exactly like a long one. */
TEST(scene_direction_length)
{
    CHECK_FAILS("{" CAM ", 'lights': [{'type': 'directional', 'direction': [1e-300, 0, -1e-300]}]}",
                "lights[0].direction", "must have a length of at least 1e-06 (shorter counts as zero), got "
                "[1e-300, 0, -1e-300] of length 1.41421e-300");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [0, 0, 0], 'up': [0, 0, 1e-7]}}", "camera.up",
                "of length 1e-07");
    CHECK_FAILS("{'camera': {'eye': [5, 0, 0], 'target': [5, 0, 1e-7]}}", "camera.target",
                "must be at least 1e-06 from eye");
    c5_err e;
    CHECK_MSG(parse("{" CAM ", 'lights': [{'type': 'directional', 'direction': [1e-6, 0, -1e-6]}]}", &e) == 0, "%s",
              e.msg);
    CHECK_VEC(scene.lights[0].direction, sqrt(0.5), 0, -sqrt(0.5));
}

/* Keys that are each valid can blend into a camera that frames nothing: up vectors that
 * cancel (the reproducer partial_output_path_up_flip.json) or an eye that passes through
 * the target. The parser refuses the scene, naming the frame, before any frame is drawn. */
TEST(scene_path_degenerate_between_keys)
{
    CHECK_FAILS("{'camera': {'eye': [4, -4, 2], 'target': [0, 0, 0]}, 'camera_path': {'frames': 3, 'keys': ["
                "{'eye': [4, -4, 2], 'target': [0, 0, 0], 'up': [0, 0, 1]},"
                "{'eye': [4, -4, 2], 'target': [0, 0, 0], 'up': [0, 0, -1]}]}}",
                "camera_path: frame 1 of 3", "up is zero or parallel to the view direction");
    CHECK_FAILS("{" CAM ", 'camera_path': {'frames': 5, 'keys': ["
                "{'eye': [2, 0, 0], 'target': [0, 0, 0]}, {'eye': [-2, 0, 0], 'target': [0, 0, 0]}]}}",
                "camera_path: frame 2 of 5", "the eye is on the target");
    /* Two frames of the same keys only visit the keys: valid. */
    c5_err e;
    CHECK_MSG(parse("{" CAM ", 'camera_path': {'frames': 2, 'keys': ["
                    "{'eye': [2, 0, 0], 'target': [0, 0, 0]}, {'eye': [-2, 0, 0], 'target': [0, 0, 0]}]}}",
                    &e) == 0,
              "%s", e.msg);
    scene.path.frames = 5;
    CHECK_INT(c5_scene_check_path(&scene, "t.json", &e), -1);
    CHECK_HAS(e.msg, "t.json: camera_path: frame 2 of 5");
}
