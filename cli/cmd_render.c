/* cube5 render: one scene through cref, a summary on stdout (text or --json). */
#include <jansson.h>
#include <zlib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cref.h"

static const char usage_text[] =
    "usage: cube5 render [SCENE|FILE.json] [-o OUT] [--threads N] [--frames N]\n"
    "                    [--size WxH] [--volume [I=]FILE] [--json]\n\n"
    "Renders a built-in scene (default: 'default'; see 'cube5 scenes') or a scene file\n"
    "with cref, the double-precision reference renderer.\n\n"
    "  -o OUT            write the image: .png (8-bit, clamped) or .exr (float); with\n"
    "                    several frames, OUT_0000.png, OUT_0001.png, ...\n"
    "  --threads N       worker threads (default: one per CPU); the image is the same\n"
    "  --frames N        frames along the scene's camera path (default: the scene's)\n"
    "  --size WxH        image size instead of the scene's\n"
    "  --volume [I=]FILE replace volume I (default 0) by a raw or NRRD file\n"
    "  --json            print one JSON object instead of the text summary; each frame\n"
    "                    has \"crc32\", a CRC-32 of its float RGB pixels\n";

typedef struct {
    const char *scene_arg, *out;
    long threads, frames;
    int w, h, json;
    const char *volumes[C5_MAX_VOLUMES];
    int n_volumes;
} render_args;

static int parse_args(int argc, char **argv, render_args *a, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->scene_arg = "default";
    int have_scene = 0;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        int has_val = i + 1 < argc;
        if (!strcmp(o, "-o") || !strcmp(o, "--threads") || !strcmp(o, "--frames") || !strcmp(o, "--size") ||
            !strcmp(o, "--volume")) {
            if (!has_val)
                return c5_fail(err, "%s: missing value", o);
            const char *v = argv[++i];
            if (!strcmp(o, "-o"))
                a->out = v;
            else if (!strcmp(o, "--threads") && c5_cli_int(o, v, 1, 256, &a->threads, err))
                return -1;
            else if (!strcmp(o, "--frames") && c5_cli_int(o, v, 1, C5_MAX_FRAMES, &a->frames, err))
                return -1;
            else if (!strcmp(o, "--size") && c5_cli_size(o, v, &a->w, &a->h, err))
                return -1;
            else if (!strcmp(o, "--volume")) {
                if (a->n_volumes == C5_MAX_VOLUMES)
                    return c5_fail(err, "--volume: at most %d", C5_MAX_VOLUMES);
                a->volumes[a->n_volumes++] = v;
            }
        } else if (!strcmp(o, "--json")) {
            a->json = 1;
        } else if (o[0] == '-') {
            return c5_fail(err, "unknown option '%s' (see 'cube5 render --help')", o);
        } else if (have_scene) {
            return c5_fail(err, "unexpected argument '%s': one scene at a time", o);
        } else {
            a->scene_arg = o;
            have_scene = 1;
        }
    }
    return 0;
}

static void add_stats(c5_cref_stats *sum, const c5_cref_stats *f)
{
    for (int t = 0; t < C5_RAY_TYPES; t++)
        sum->rays[t] += f->rays[t];
    for (int e = 0; e < C5_END_KINDS; e++)
        sum->ends[e] += f->ends[e];
    sum->samples += f->samples;
    sum->wall_s += f->wall_s;
}

static json_t *stats_json(const c5_cref_stats *st)
{
    json_t *rays = json_object(), *ends = json_object();
    for (int t = 0; t < C5_RAY_TYPES; t++)
        json_object_set_new(rays, c5_ray_type_name(t), json_integer((json_int_t)st->rays[t]));
    for (int e = 0; e < C5_END_KINDS; e++)
        json_object_set_new(ends, c5_end_kind_name(e), json_integer((json_int_t)st->ends[e]));
    return json_pack("{s:o, s:I, s:o, s:f}", "rays", rays, "samples", (json_int_t)st->samples, "ends", ends,
                     "wall_s", st->wall_s);
}

static void print_text(const char *label, const c5_scene *s, const c5_supervol *sv, int frames, int threads,
                       const c5_cref_stats *st, const char *out)
{
    printf("cube5 render: %s, %dx%d, %d frame(s), cref (double), %d thread(s)\n", label, s->render.width,
           s->render.height, frames, threads);
    if (c5_supervol_empty(sv)) {
        printf("  volume   none\n");
    } else {
        for (int i = 0; i < sv->n_sources; i++)
            printf("  volume   %s\n", sv->source_label[i]);
        printf("  grid     %zux%zux%zu voxels, spacing %g %g %g, step %g\n", sv->dims[0], sv->dims[1], sv->dims[2],
               sv->spacing.x, sv->spacing.y, sv->spacing.z, c5_render_step(s, sv));
    }
    printf("  scene    %d surface(s), %d light(s), max %d bounce(s)\n", s->n_surfaces, s->n_lights,
           s->render.max_bounces);
    printf("  rays     eye %llu, shadow %llu, reflect %llu, refract %llu\n", (unsigned long long)st->rays[0],
           (unsigned long long)st->rays[1], (unsigned long long)st->rays[2], (unsigned long long)st->rays[3]);
    printf("  samples  %llu\n  ends    ", (unsigned long long)st->samples);
    for (int e = 0; e < C5_END_KINDS; e++)
        printf(" %s %llu%s", c5_end_kind_name(e), (unsigned long long)st->ends[e], e + 1 < C5_END_KINDS ? "," : "\n");
    printf("  time     %.3f s\n", st->wall_s);
    printf("  image    %s\n", out ? out : "not written (give -o OUT)");
}

int c5_cmd_render(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(usage_text, stdout);
            return 0;
        }
    render_args a;
    c5_err err;
    static c5_scene s;
    char label[1100];
    c5_supervol sv = {0};
    int rc = C5_EXIT_INPUT;
    if (parse_args(argc, argv, &a, &err) != 0 || c5_cli_load_scene(a.scene_arg, &s, label, sizeof label, &err) != 0)
        goto fail;
    for (int i = 0; i < a.n_volumes; i++)
        if (c5_cli_replace_volume(&s, a.volumes[i], &err) != 0)
            goto fail;
    if (a.w) {
        s.render.width = a.w;
        s.render.height = a.h;
    }
    if (a.frames) {
        s.path.frames = (int)a.frames;
        if (s.path.n_keys == 0 && a.frames > 1) {
            err = (c5_err){"--frames: the scene has no camera_path"};
            goto fail;
        }
    }
    if (a.out && c5_cli_check_output(a.out, a.scene_arg, &s, &err) != 0)
        goto fail;
    if (c5_supervol_build(&s, &sv, &err) != 0)
        goto fail;

    int frames = c5_scene_frames(&s);
    c5_cref_opts opts = {.threads = (int)a.threads};
    c5_cref_stats total = {0};
    json_t *per_frame = json_array(), *outputs = json_array();
    rc = 0;
    for (int f = 0; f < frames && rc == 0; f++) {
        c5_image img;
        c5_cref_stats st;
        if (c5_cref_render(&s, &sv, f, &opts, &img, &st, &err) != 0) {
            rc = C5_EXIT_RUNTIME;
            break;
        }
        add_stats(&total, &st);
        json_t *fj = stats_json(&st);
        /* CRC-32 of the frame's float RGB bytes: a bit-exact fingerprint of the image. */
        uLong crc = crc32(0L, (const Bytef *)img.rgb, (uInt)(sizeof(float) * 3 * (size_t)img.w * img.h));
        json_object_set_new(fj, "crc32", json_sprintf("%08lx", (unsigned long)crc));
        json_array_append_new(per_frame, fj);
        if (a.out) {
            char path[2048];
            c5_cli_frame_path(a.out, f, frames, path, sizeof path);
            if (c5_image_write(path, &img, &err) != 0)
                rc = C5_EXIT_RUNTIME;
            else
                json_array_append_new(outputs, json_string(path));
        }
        c5_image_free(&img);
    }
    if (rc == 0) {
        int threads = c5_cref_thread_count((int)a.threads);
        if (a.json) {
            json_t *o = stats_json(&total);
            json_object_set_new(o, "renderer", json_string("cref"));
            json_object_set_new(o, "scene", json_string(s.name));
            json_object_set_new(o, "width", json_integer(s.render.width));
            json_object_set_new(o, "height", json_integer(s.render.height));
            json_object_set_new(o, "threads", json_integer(threads));
            json_object_set_new(o, "frames", per_frame);
            json_object_set_new(o, "outputs", outputs);
            per_frame = outputs = NULL;
            char *text = json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(9));
            puts(text);
            free(text);
            json_decref(o);
        } else {
            print_text(label, &s, &sv, frames, threads, &total, frames > 1 && a.out ? "one file per frame" : a.out);
        }
    }
    json_decref(per_frame);
    json_decref(outputs);
    c5_supervol_free(&sv);
    if (rc == 0)
        return 0;
fail:
    c5_supervol_free(&sv);
    fprintf(stderr, "cube5: error: %s\n", err.msg);
    return rc;
}
