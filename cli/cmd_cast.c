/* cube5 cast: the streaming-model caster (cref/cast, docs/caster.md) over the peer benchmark's
 * views of a volume, timed per view: fps as the median over the views, producer against
 * worker time, load balance. The input is a volume file, a phantom of render_vtk.py, or a
 * scene (its grid and transfer function). */
#include <jansson.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <errno.h>
#include <unistd.h>

#include "cast_peer.h"
#include "atomic_file.h"
#include "cli.h"
#include "volume.h"
#include "clock.h"
#include "progress.h"

typedef struct {
    const char *input, *out, *tf, *save_raw;
    long views, threads, queue_depth, repeats, seed;
    int size, producer, shading, k, sub_bricks, self_produce, wide, json;
    c5_cast_prefetch prefetch;
    c5_cast_mode mode;
    double distance, step;
    size_t dims[3];
    double spacing[3];
    int has_dims, has_spacing;
} args;

static int on_off(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    if (!strcmp(v, "on") || !strcmp(v, "off")) {
        *(int *)field = !strcmp(v, "on");
        return 0;
    }
    return c5_fail(err, "%s: expected on or off, got '%s'", o->name, v);
}

static int on_off_auto(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    if (!strcmp(v, "auto")) {
        *(int *)field = -1;
        return 0;
    }
    if (on_off(o, v, field, err))
        return c5_fail(err, "%s: expected on, off or auto, got '%s'", o->name, v);
    return 0;
}

static int size_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    int w, h;
    if (c5_cli_size(o->name, v, &w, &h, err))
        return -1;
    if (w != h)
        return c5_fail(err, "%s: the caster's views are square (the peer's); give N or NxN, got '%s'", o->name, v);
    *(int *)field = w;
    return 0;
}

static int k_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    long n;
    if (c5_cli_int(o->name, v, 1, 16, &n, err))
        return -1;
    if (n & (n - 1))
        return c5_fail(err, "%s: expected 1, 2, 4, 8 or 16, got '%s'", o->name, v);
    *(int *)field = (int)n;
    return 0;
}

static int mode_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    if (c5_cast_mode_parse(v, field))
        return c5_fail(err, "%s: expected plain, ess, approx or approx+refine, got '%s'", o->name, v);
    return 0;
}

static int prefetch_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    if (c5_cast_prefetch_parse(!strcmp(v, "on") ? "cells" : v, field))
        return c5_fail(err, "%s: expected cells, bricks, off or on, got '%s'", o->name, v);
    return 0;
}

static int parse_triple(const char *opt, const char *v, char sep, double out[3], c5_err *err)
{
    char *end;
    const char *p = v;
    for (int i = 0; i < 3; i++) {
        out[i] = strtod(p, &end);
        if (end == p || !(out[i] > 0) || !isfinite(out[i]) || *end != (i < 2 ? sep : 0))
            return c5_fail(err, "%s: expected three positive numbers separated by '%c', got '%s'", opt, sep, v);
        p = end + 1;
    }
    return 0;
}

static int dims_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    double d[3];
    size_t *dims = field;
    if (parse_triple(o->name, v, 'x', d, err))
        return -1;
    for (int k = 0; k < 3; k++) {
        if (d[k] != floor(d[k]) || d[k] > C5_VOLUME_MAX_DIM)
            return c5_fail(err, "%s: expected whole numbers 1..%u, got '%s'", o->name, C5_VOLUME_MAX_DIM, v);
        dims[k] = (size_t)d[k];
    }
    return 0;
}

static int spacing_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    return parse_triple(o->name, v, ',', field, err);
}

static const c5_opt opts[] = {
    {"-o", "OUT", c5_opt_str, offsetof(args, out), 0, 0, 0, "write the first view (.png or .exr)"},
    {"--views", "N", c5_opt_long, offsetof(args, views), 1, 1000, 0, "views 1..1000 (default 24)"},
    {"--size", "N|NxN", size_opt, offsetof(args, size), 0, 0, 0,
     "image N x N, 1..4096 (default 256; square, as the peer's views)"},
    {"--mode", "M", mode_opt, offsetof(args, mode), 0, 0, 0,
     "plain | ess | approx | approx+refine (default approx: with sub-bricks the refining hash drops no sample they "
     "keep, docs/caster.md)"},
    {"--threads", "N", c5_opt_long, offsetof(args, threads), 1, C5_CAST_MAX_WORKERS, 0,
     "worker threads 1..64 (default 2)"},
    {"--producer", "on|off|auto", on_off_auto, offsetof(args, producer), 0, 0, 0,
     "the calling thread produces tiles for the workers' buffers; off: the workers produce all their tiles (default "
     "auto: on while there are fewer workers than CPUs)"},
    {"--shading", "on|off", on_off, offsetof(args, shading), 0, 0, 0, "headlight Blinn-Phong (default off)"},
    {"--k", "N", k_opt, offsetof(args, k), 0, 0, 0,
     "approximation interval 1,2,4,8,16 (default: Proposition 1's per view, raised to 4 and capped at 8; any k "
     "draws the same bits)"},
    {"--prefetch", "P", prefetch_opt, offsetof(args, prefetch), 0, 0, 0,
     "cells: the cache lines of each sample's cell, a batch of samples ahead (default; on is the same); bricks: the "
     "paper's, the whole next brick along each ray on entering a brick; off"},
    {"--sub-bricks", "on|off", on_off, offsetof(args, sub_bricks), 0, 0, 0,
     "skipping modes: drop samples in 4^3-cell sub-bricks the TF leaves empty (default on)"},
    {"--queue-depth", "N", c5_opt_long, offsetof(args, queue_depth), 1, 1024, 0,
     "tasks each worker's buffer holds, 1..1024 (default 4, the paper's)"},
    {"--self-produce", "on|off", on_off, offsetof(args, self_produce), 0, 0, 0,
     "a worker with an empty buffer produces its next tile itself instead of waiting for the producer thread "
     "(default on)"},
    {"--wide", "on|off|auto", on_off_auto, offsetof(args, wide), 0, 0, 0,
     "eight samples at a time with AVX2, except approx+refine and --prefetch bricks (same bits; default auto: where "
     "the CPU has it; on: "
     "refused where it cannot run)"},
    {"--distance", "F", c5_opt_double, offsetof(args, distance), 1e-3, 1e6, 0,
     "eye distance in bounding-sphere radii (default 3.8637 = 1/sin 15deg)"},
    {"--tf", "NAME|FILE", c5_opt_str, offsetof(args, tf), 0, 0, 0,
     "default | ml | a TF file of the peer's format (default: default, or the scene's transfer function)"},
    {"--step", "S", c5_opt_double, offsetof(args, step), 1e-3, 1e3, 0,
     "sample distance in voxels (times the smallest spacing; default 1)"},
    {"--seed", "N", c5_opt_long, offsetof(args, seed), 0, 0x7fffffffL, 0, "camera stream seed (default 1)"},
    {"--repeats", "N", c5_opt_long, offsetof(args, repeats), 1, 100, 0,
     "passes over the views; the median of the per-pass medians (default 1)"},
    {"--dims", "XxYxZ", dims_opt, offsetof(args, dims), 0, 0, C5_SEEN(args, has_dims),
     "dims of a raw file whose name does not give them"},
    {"--spacing", "X,Y,Z", spacing_opt, offsetof(args, spacing), 0, 0, C5_SEEN(args, has_spacing),
     "voxel spacing (default 1,1,1, or the NRRD header's)"},
    {"--save-raw", "FILE", c5_opt_str, offsetof(args, save_raw), 0, 0, 0,
     "write the voxels cast as raw uint8 (for the peer: render_vtk.py --raw)"},
    {"--json", NULL, c5_opt_flag, offsetof(args, json), 0, 0, 0, "the figures as JSON on stdout"},
    {0},
};

const c5_cmd_spec c5_spec_cast = {
    "cast", "VOLUME|SCENE",
    "Renders the peer benchmark's views (../shared/bench/peer-vtk conventions: SplitMix64 cameras around the "
    "volume, 30-degree perspective, its transfer-function files) with the streaming-model ray caster and reports "
    "frames per second as the median over the views.\n\n"
    "VOLUME is a uint8 .raw file (dims from an Open SciVis name NAME_XxYxZ_uint8.raw, or --dims), a .nrrd/.nhdr "
    "file, or phantom:ml:N / phantom:shell:N (render_vtk.py's synthetic volumes). SCENE is a built-in scene or a "
    "scene .json: its grid and transfer function are cast.",
    {{opts, 0}, {c5_progress_opts, 0}},
};

static int parse_args(int argc, char **argv, args *a, c5_err *err)
{
    *a = (args){.tf = NULL, .views = 24, .size = 256, .threads = 2, .producer = -1, .k = 0,
                .prefetch = C5_CAST_PREFETCH_CELLS,
                .sub_bricks = 1, .self_produce = 1, .wide = -1, .queue_depth = 4, .repeats = 1,
                .mode = C5_CAST_APPROX, .distance = C5_PEER_DISTANCE_FIT, .step = 1, .seed = 1,
                .spacing = {1, 1, 1}};
    if (c5_opt_parse(&c5_spec_cast, argc, argv, a, &a->input, err) != 0)
        return -1;
    if (!a->input)
        return c5_fail(err, "cast needs a VOLUME or SCENE (see cube5 cast --help)");
    if (a->producer == 0 && !a->self_produce)
        return c5_fail(err, "--producer off needs --self-produce on: with no producer thread the workers "
                            "produce their own tiles");
    return 0;
}

/* What is cast: voxels, their geometry, the transfer function, a name for the report. */
typedef struct {
    uint8_t *vox;
    size_t dims[3];
    double spacing[3];
    c5_tf_desc tf;
    char name[256];
} input;

static int has_ext(const char *p, const char *ext)
{
    size_t n = strlen(p), e = strlen(ext);
    return n > e && !strcasecmp(p + n - e, ext);
}

static int load_input(const args *a, input *in, c5_err *err)
{
    const char *tf = a->tf ? a->tf : "default";
    memcpy(in->spacing, a->spacing, sizeof in->spacing);
    if (!strncmp(a->input, "phantom:", 8)) {
        c5_phantom kind;
        char k[16];
        long n;
        const char *colon = strchr(a->input + 8, ':');
        size_t len = colon ? (size_t)(colon - a->input - 8) : 0;
        if (!colon || len >= sizeof k)
            return c5_fail(err, "%s: expected phantom:ml:N or phantom:shell:N", a->input);
        memcpy(k, a->input + 8, len);
        k[len] = 0;
        if (c5_phantom_parse(k, &kind))
            return c5_fail(err, "%s: unknown phantom '%s' (ml or shell)", a->input, k);
        if (c5_cli_int("phantom size", colon + 1, 2, 1024, &n, err))
            return -1;
        for (int i = 0; i < 3; i++)
            in->dims[i] = (size_t)n;
        size_t budget, count = (size_t)n * (size_t)n * (size_t)n;
        if (c5_mem_budget(&budget, err) != 0)
            return -1;
        if (count > budget) /* as for a file: the caster holds its volume in memory */
            return c5_fail(err, "%s: %ldx%ldx%ld voxels are above the memory budget (C5_MEM_BUDGET, here %zu bytes): "
                                "the caster needs the whole volume in memory; raise C5_MEM_BUDGET",
                           a->input, n, n, n, budget);
        if (!(in->vox = c5_phantom_make(kind, (size_t)n)))
            return c5_fail(err, "%s: out of memory", a->input);
        snprintf(in->name, sizeof in->name, "synthetic_%s_%ld", k, n);
        if (!a->tf && kind == C5_PHANTOM_ML)
            tf = "ml";
    } else if (has_ext(a->input, ".raw") || has_ext(a->input, ".nrrd") || has_ext(a->input, ".nhdr")) {
        c5_raw_spec spec = {.type = a->has_dims ? C5_VOX_U8 : C5_VOX_NONE};
        memcpy(spec.dims, a->dims, sizeof spec.dims);
        /* opened and checked without reading (c5_volume_open), sized against the memory
         * budget, then read whole: the caster holds its volume in memory */
        c5_volume_file v;
        size_t budget, count;
        if (c5_mem_budget(&budget, err) || c5_volume_open(a->input, &spec, &v, err))
            return -1;
        if (v.type != C5_VOX_U8) {
            close(v.fd);
            return c5_fail(err, "%s: cast takes uint8 volumes (the peer's convention); use the _uint8 file or a "
                                "scene with a window",
                           a->input);
        }
        count = v.dims[0] * v.dims[1] * v.dims[2];
        if (count > budget) {
            close(v.fd);
            return c5_fail(err, "%s: %zux%zux%zu voxels are above the memory budget (C5_MEM_BUDGET, here %zu bytes): "
                                "the caster needs the whole volume in memory; raise C5_MEM_BUDGET or render with cref",
                           a->input, v.dims[0], v.dims[1], v.dims[2], budget);
        }
        if (!(in->vox = malloc(count))) {
            close(v.fd);
            return c5_fail(err, "%s: out of memory for %zu voxels", a->input, count);
        }
        for (size_t got = 0; got < count;) {
            ssize_t r = pread(v.fd, in->vox + got, count - got, (off_t)(v.offset + (long long)got));
            if (r <= 0 && !(r < 0 && errno == EINTR)) {
                close(v.fd);
                return c5_fail(err, "%s: read failed: %s", a->input, r < 0 ? strerror(errno) : "the file ends early");
            }
            got += r > 0 ? (size_t)r : 0;
        }
        close(v.fd);
        memcpy(in->dims, v.dims, sizeof in->dims);
        if (!a->has_spacing && v.spacing[0] > 0 && v.spacing[1] > 0 && v.spacing[2] > 0)
            memcpy(in->spacing, v.spacing, sizeof in->spacing);
        const char *base = strrchr(a->input, '/');
        snprintf(in->name, sizeof in->name, "%s", base ? base + 1 : a->input);
        char *dot = strrchr(in->name, '.');
        if (dot)
            *dot = 0;
    } else {
        c5_scene s;
        c5_supervol sv;
        char label[512];
        if (c5_cli_scene_setup(a->input, NULL, 0, 0, &s, label, sizeof label, err) ||
            c5_supervol_build(&s, &sv, err))
            return -1;
        if (c5_supervol_empty(&sv)) {
            c5_supervol_free(&sv);
            return c5_fail(err, "%s: the scene has no volume to cast", label);
        }
        if (!sv.v) {
            int rc = c5_supervol_cast_refusal(&sv, label, err);
            c5_supervol_free(&sv);
            return rc;
        }
        memcpy(in->dims, sv.dims, sizeof in->dims);
        double sp[3] = {sv.spacing.x, sv.spacing.y, sv.spacing.z};
        memcpy(in->spacing, sp, sizeof sp);
        if (!(in->vox = c5_supervol_detach(&sv)))
            return c5_fail(err, "%s: out of memory for %zu voxels", label, in->dims[0] * in->dims[1] * in->dims[2]);
        snprintf(in->name, sizeof in->name, "%s", a->input);
        if (!a->tf) {
            in->tf = s.tf;
            if (!(in->tf.unit_distance > 0))
                in->tf.unit_distance = fmin(sp[0], fmin(sp[1], sp[2]));
            return 0;
        }
    }
    return c5_peer_tf_load(tf, fmin(in->spacing[0], fmin(in->spacing[1], in->spacing[2])), &in->tf, err);
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Per view, the last pass's figures (the counts are the same in every pass). */
typedef struct {
    double ms, producer_ms, worker_ms, imbalance;
    int prop1_k; /* Proposition 1's k for the view, beside the k the frame took */
    c5_cast_stats st;
} view_fig;

static int write_raw(const char *path, const input *in, c5_err *err)
{
    return c5_afile_put(path, in->vox, in->dims[0] * in->dims[1] * in->dims[2], err);
}

/* The files cast reads: the volume (and a NRRD header's data files) or the scene's files,
 * and a transfer-function file. */
static int cast_inputs(const args *a, c5_file_list *in, c5_err *err)
{
    if (a->tf && c5_file_list_add(in, a->tf, "the transfer function file", err) != 0)
        return -1;
    if (!strncmp(a->input, "phantom:", 8))
        return 0;
    if (has_ext(a->input, ".raw") || has_ext(a->input, ".nrrd") || has_ext(a->input, ".nhdr"))
        return c5_volume_input_files(a->input, "the input volume", in, err);
    static c5_scene s;
    char label[512];
    return c5_cli_load_scene(a->input, &s, label, sizeof label, err) != 0 ||
                   c5_cli_scene_inputs(a->input, &s, in, err) != 0
               ? -1
               : 0;
}

/* -o and --save-raw: checked before anything is read or written. */
static int check_outputs(const args *a, c5_err *err)
{
    c5_file_list in = {0};
    int rc = cast_inputs(a, &in, err) != 0 || (a->out && c5_cli_check_image_out(a->out, &in, err) != 0) ||
             (a->save_raw && (c5_cli_check_not_input(a->save_raw, &in, err) != 0 ||
                              c5_output_check(a->save_raw, err) != 0)) ||
             (a->out && a->save_raw && c5_cli_check_distinct_frames(a->out, 1, "-o", a->save_raw, "--save-raw", err) != 0);
    c5_file_list_free(&in);
    return rc ? -1 : 0;
}

/* The figures over the views: medians, means, the range of k. */
typedef struct {
    double ms_med, mean, prod, work, imb, samples, setup_ms;
    int k_min, k_max;
} cast_summary;

static cast_summary summarise(const view_fig *fig, int views, double *pass_median, int repeats, double setup_ms)
{
    cast_summary m = {.ms_med = median(pass_median, repeats), .setup_ms = setup_ms, .k_min = 16, .k_max = 1};
    for (int i = 0; i < views; i++) {
        m.prod += fig[i].producer_ms / views, m.work += fig[i].worker_ms / views;
        m.imb += fig[i].imbalance / views, m.samples += (double)fig[i].st.samples / views;
        m.mean += fig[i].ms / views;
        m.k_min = fig[i].st.k < m.k_min ? fig[i].st.k : m.k_min, m.k_max = fig[i].st.k > m.k_max ? fig[i].st.k : m.k_max;
    }
    return m;
}

static void print_json(const args *a, const input *in, const view_fig *fig, const cast_summary *m)
{
    json_t *j = json_object(), *per = json_array();
    for (int i = 0; i < a->views; i++) {
        const c5_cast_stats *s = &fig[i].st;
        json_array_append_new(
            per, json_pack("{s:f,s:f,s:f,s:f,s:i,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:b,s:b,s:i}", "ms", fig[i].ms, "producer_ms",
                           fig[i].producer_ms, "worker_ms", fig[i].worker_ms, "load_imbalance_pct", fig[i].imbalance,
                           "k", s->k, "producer_rays", (json_int_t)s->producer_rays, "segments",
                           (json_int_t)s->segments, "samples", (json_int_t)s->samples, "samples_zero",
                           (json_int_t)s->samples_zero, "samples_hashed", (json_int_t)s->samples_hashed,
                           "samples_sub", (json_int_t)s->samples_sub, "rays_terminated",
                           (json_int_t)s->rays_terminated, "tiles_self_produced", (json_int_t)s->tiles_self,
                           "producer_thread", s->producer, "wide", s->wide, "prop1_k", fig[i].prop1_k));
    }
    json_object_set_new(j, "dataset",
                        json_pack("{s:s,s:[I,I,I],s:[f,f,f]}", "name", in->name, "dims", (json_int_t)in->dims[0],
                                  (json_int_t)in->dims[1], (json_int_t)in->dims[2], "spacing", in->spacing[0],
                                  in->spacing[1], in->spacing[2]));
    json_object_update_new(
        j, json_pack("{s:s,s:i,s:b,s:b,s:s,s:b,s:b,s:i,s:i,s:f,s:f,s:i,s:I}", "mode", c5_cast_mode_name(a->mode),
                     "threads", (int)a->threads, "producer_thread", fig[0].st.producer, "shading", a->shading,
                     "prefetch", c5_cast_prefetch_name(a->prefetch), "sub_bricks", a->sub_bricks, "self_produce",
                     a->self_produce, "size", a->size, "views", (int)a->views, "distance_factor", a->distance,
                     "step_voxels", a->step, "repeats", (int)a->repeats, "seed", (json_int_t)a->seed));
    json_object_update_new(
        j, json_pack("{s:f,s:f,s:f,s:f,s:f,s:f,s:f,s:i,s:i,s:o}", "fps_median", 1000 / m->ms_med, "ms_median",
                     m->ms_med, "ms_mean", m->mean, "producer_ms_mean", m->prod, "worker_ms_mean", m->work,
                     "load_imbalance_pct_mean", m->imb, "setup_ms", m->setup_ms, "k_min", m->k_min, "k_max", m->k_max,
                     "per_view", per));
    json_object_set_new(j, "samples_mean", json_real(m->samples));
    json_t *outputs = json_array();
    if (a->out)
        json_array_append_new(outputs, json_string(a->out));
    if (a->save_raw)
        json_array_append_new(outputs, json_string(a->save_raw));
    json_object_set_new(j, "outputs", outputs);
    char *text = json_dumps(j, JSON_COMPACT);
    puts(text);
    free(text);
    json_decref(j);
}

static void print_text(const args *a, const input *in, const cast_summary *m)
{
    printf("%s %zux%zux%zu, %ld views at %dx%d, mode %s, k %d..%d, %ld worker%s, shading %s, prefetch %s, "
           "sub-bricks %s\n",
           in->name, in->dims[0], in->dims[1], in->dims[2], a->views, a->size, a->size, c5_cast_mode_name(a->mode),
           m->k_min, m->k_max, a->threads, a->threads == 1 ? "" : "s", a->shading ? "on" : "off",
           c5_cast_prefetch_name(a->prefetch), a->sub_bricks ? "on" : "off");
    printf("median %.2f ms/frame (%.1f fps), mean %.2f ms; producer %.2f ms, worker %.2f ms per frame; "
           "load imbalance %.1f%%; %.0f samples per frame; setup %.0f ms\n",
           m->ms_med, 1000 / m->ms_med, m->mean, m->prod, m->work, m->imb, m->samples, m->setup_ms);
    if (a->out)
        printf("image %s (the first view)\n", a->out);
    if (a->save_raw)
        printf("voxels %s (raw uint8, %zux%zux%zu)\n", a->save_raw, in->dims[0], in->dims[1], in->dims[2]);
}

int c5_cmd_cast(int argc, char **argv)
{
    if (c5_opt_help(&c5_spec_cast, argc, argv))
        return 0;
    c5_err err;
    args a;
    input in = {0};
    c5_cast_volume *cv = NULL;
    c5_cast_camera *cams = NULL;
    view_fig *fig = NULL;
    double *pass_median = NULL, *tmp = NULL;
    c5_image img = {0};
    c5_progress prog = {0};
    int rc = C5_EXIT_INPUT;
    if (parse_args(argc, argv, &a, &err))
        goto fail;
    if (check_outputs(&a, &err) != 0)
        goto fail;
    double t0 = c5_now_s();
    if (load_input(&a, &in, &err) || c5_cast_volume_make(in.vox, in.dims, in.spacing, &cv, &err))
        goto fail;
    rc = C5_EXIT_RUNTIME;
    if (a.shading && c5_cast_volume_normals(cv, &err))
        goto fail;
    double setup_ms = (c5_now_s() - t0) * 1e3;
    if (a.save_raw && write_raw(a.save_raw, &in, &err))
        goto fail;
    double ms_sp = fmin(in.spacing[0], fmin(in.spacing[1], in.spacing[2]));
    c5_cast_tf tf;
    rc = C5_EXIT_INPUT;
    if (c5_cast_tf_build(&in.tf, a.step * ms_sp, in.tf.unit_distance, &tf, &err))
        goto fail;
    rc = C5_EXIT_RUNTIME;
    cams = calloc((size_t)a.views, sizeof *cams);
    fig = calloc((size_t)a.views, sizeof *fig);
    pass_median = calloc((size_t)a.repeats, sizeof *pass_median);
    tmp = calloc((size_t)a.views, sizeof *tmp);
    if (!cams || !fig || !pass_median || !tmp) {
        c5_fail(&err, "out of memory");
        goto fail;
    }
    c5_peer_cameras(in.dims, in.spacing, a.views, (uint64_t)a.seed, a.distance, C5_PEER_VIEW_ANGLE, cams);
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    o.mode = a.mode, o.k = a.k, o.workers = a.threads, o.shading = a.shading, o.prefetch = a.prefetch;
    o.sub_bricks = a.sub_bricks, o.queue_depth = a.queue_depth, o.self_produce = a.self_produce;
    o.producer = a.producer, o.wide = a.wide;
    o.step = a.step * ms_sp;
    c5_progress_begin(&prog, "cast", a.repeats * a.views);
    for (int p = 0; p < a.repeats; p++) {
        for (int i = 0; i < a.views; i++) {
            view_fig *f = &fig[i];
            if (c5_cast_render(cv, &tf, &cams[i], a.size, a.size, &o, &img, &f->st, &err))
                goto fail;
            f->ms = f->st.frame_s * 1e3, f->producer_ms = f->st.producer_s * 1e3;
            f->worker_ms = 0;
            for (int w = 0; w < f->st.workers; w++)
                f->worker_ms += f->st.worker_s[w] * 1e3 / f->st.workers;
            f->imbalance = c5_cast_load_imbalance(&f->st);
            f->prop1_k = c5_cast_prop1_k(cv, &cams[i], a.size, a.size);
            tmp[i] = f->ms;
            if (i == 0 && p == 0 && a.out && c5_image_write(a.out, &img, &err))
                goto fail;
            c5_progress_step(&prog, p * a.views + i + 1, "view %d: %.2f ms", i, f->ms);
        }
        pass_median[p] = median(tmp, a.views);
    }
    c5_progress_end(&prog);
    cast_summary sum = summarise(fig, (int)a.views, pass_median, (int)a.repeats, setup_ms);
    if (a.json)
        print_json(&a, &in, fig, &sum);
    else
        print_text(&a, &in, &sum);
    rc = 0;
    goto done;
fail:
    c5_progress_end(&prog);
    fprintf(stderr, "cube5: error: %s\n", err.msg);
done:
    c5_image_free(&img);
    c5_cast_volume_free(cv);
    free(in.vox);
    free(cams);
    free(fig);
    free(pass_median);
    free(tmp);
    return rc;
}
