/* cube5 compare: one frame through cref and through the board model, the difference
 * (docs/compare.md) and the cost of each, on stdout (text or --json). */
#include <jansson.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "board.h"
#include "boards_cli.h"
#include "cli.h"
#include "cref.h"
#include "metrics.h"
#include "clock.h"
#include "progress.h"

typedef struct {
    const char *scene_arg, *diff;
    long threads, frame;
    int size[2], json, ref_long;
    double gain;
    c5_cli_volumes volumes;
    int cells[3];
    c5_queue_key key;
    c5_boards_args bd;
} compare_args;

static int precision_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    static const char *const names[] = {"double", "long", NULL};
    return c5_opt_pick(o, v, names, 0, field, err);
}

static const c5_opt opts[] = {
    {"--cells", "N|NxMxK", c5_opt_cells, offsetof(compare_args, cells), 0, 0, 0,
     "split the grid into NxNxN (or NxMxK) cells for the model (default 1, or the fewest that keep a cell within "
     "256 voxels a side)"},
    {"--queue-key", "morton|fifo", c5_opt_queue_key, offsetof(compare_args, key), 0, 0, 0,
     "order of the model's ray queue (default morton)"},
    {"--size", "N|WxH", c5_opt_size, offsetof(compare_args, size), 0, 0, 0, "image size instead of the scene's (N: NxN)"},
    {"--frame", "I", c5_opt_long, offsetof(compare_args, frame), 0, C5_MAX_FRAMES - 1, 0,
     "frame I (from 0) of the scene's camera path (default 0)"},
    {"--diff", "OUT", c5_opt_str, offsetof(compare_args, diff), 0, 0, 0,
     "write |model - cref| x G as an image: .png (clamped) or .exr (float)"},
    /* 1e-6..1e6: at 1e6 an error of 1e-6 is white already; below 1e-6 no error in [0,1] shows. */
    {"--gain", "G", c5_opt_double, offsetof(compare_args, gain), 1e-6, 1e6, 0,
     "G for --diff (default 16: one 8-bit step shows as 16)"},
    {"--json", NULL, c5_opt_flag, offsetof(compare_args, json), 0, 0, 0, "print one JSON object instead of the text"},
    {"--volume", "[I=]FILE", c5_opt_volume, offsetof(compare_args, volumes), 0, 0, 0,
     "replace volume I (default 0) by a raw or NRRD file"},
    {"--threads", "N", c5_opt_long, offsetof(compare_args, threads), 1, 256, 0,
     "cref's worker threads (default: one per CPU); the model uses one"},
    {"--ref-precision", "double|long", precision_opt, offsetof(compare_args, ref_long), 0, 0, 0,
     "cref in double (default) or long (long double; docs/stability.md)"},
    {0},
};

const c5_cmd_spec c5_spec_compare = {
    "compare", "[SCENE|FILE.json]",
    "Renders one frame of a scene (default: 'default') with cref, the reference, and with the bit-accurate board "
    "model, then prints how far the model's image is from cref's (PSNR, RMSE, largest error, overall and per "
    "channel, and a histogram of the errors in 8-bit steps) and what each cost. Definitions: docs/compare.md.",
    {{opts, 0}, {c5_boards_opts, offsetof(compare_args, bd)}, {c5_progress_opts, 0}},
};

static int parse_args(int argc, char **argv, compare_args *a, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->scene_arg = "default";
    a->gain = C5_DIFF_GAIN;
    a->cells[0] = a->cells[1] = a->cells[2] = 0; /* the automatic split */
    a->key = C5_KEY_MORTON;
    return c5_opt_parse(&c5_spec_compare, argc, argv, a, &a->scene_arg, err);
}

/* What the two runs produced. Host times are measured here, around each call, so that both
 * are timed the same way whatever the renderers report. */
typedef struct {
    c5_image ref, test;
    c5_cref_stats cref;
    c5_board_stats board;
    double cref_wall_s, model_wall_s;
    c5_image_diff d;
    c5_mb_stats mb;          /* with --boards */
} compare_result;

static json_t *triple(const double v[3])
{
    return json_pack("[f, f, f]", v[0], v[1], v[2]);
}

static void print_json(const compare_args *a, const c5_scene *s, int threads, const compare_result *r)
{
    const c5_image_diff *d = &r->d;
    json_t *hist = json_array();
    for (int i = 0; i < C5_METRIC_BINS; i++)
        json_array_append_new(hist, json_pack("{s:s, s:I}", "label", c5_metric_bin_label(i), "count",
                                              (json_int_t)d->hist[i]));
    json_t *o = json_object();
    json_object_set_new(o, "scene", json_string(s->name));
    json_object_set_new(o, "size", json_pack("[i, i]", s->render.width, s->render.height));
    json_object_set_new(o, "frame", json_integer(a->frame));
    json_object_set_new(o, "cells", json_integer(a->cells[0] * a->cells[1] * a->cells[2]));
    json_object_set_new(o, "cells_split", json_pack("[i, i, i]", a->cells[0], a->cells[1], a->cells[2]));
    json_object_set_new(o, "queue_key", json_string(c5_cli_queue_key_name(a->key)));
    json_object_set_new(o, "threads", json_integer(threads));
    json_object_set_new(o, "ref_precision", json_string(a->ref_long ? "long" : "double"));
    json_object_set_new(o, "identical", json_boolean(d->rmse == 0.0));
    json_object_set_new(o, "psnr_db", json_real(d->psnr_db));
    json_object_set_new(o, "rmse", json_real(d->rmse));
    json_object_set_new(o, "max_abs_err", json_real(d->max_abs_err));
    json_object_set_new(o, "psnr_ch", triple(d->psnr_ch));
    json_object_set_new(o, "rmse_ch", triple(d->rmse_ch));
    json_object_set_new(o, "max_abs_ch", triple(d->max_abs_ch));
    json_object_set_new(o, "values", json_integer((json_int_t)d->values));
    json_object_set_new(o, "differing", json_integer((json_int_t)d->differing));
    json_object_set_new(o, "histogram", hist);
    json_object_set_new(o, "cref_wall_s", json_real(r->cref_wall_s));
    json_object_set_new(o, "model_wall_s", json_real(r->model_wall_s));
    json_object_set_new(o, "board_cycles", json_integer((json_int_t)r->board.cycles));
    json_object_set_new(o, "board_s", json_real(r->board.board_s));
    json_object_set_new(o, "fetches", json_integer((json_int_t)r->board.fetches));
    json_object_set_new(o, "fetch_bytes", json_integer((json_int_t)r->board.fetch_bytes));
    json_object_set_new(o, "board", c5_cli_board_json(&r->board));
    if (a->bd.given)
        json_object_set_new(o, "multi_board", c5_cli_mb_json(&r->mb));
    json_object_set_new(o, "diff", a->diff ? json_string(a->diff) : json_null());
    json_object_set_new(o, "diff_gain", json_real(a->gain));
    json_object_set_new(o, "outputs", a->diff ? json_pack("[s]", a->diff) : json_array());
    char *text = json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(9));
    puts(text);
    free(text);
    json_decref(o);
}

/* "inf" for identical images, ">= 200" when capped, else the value. */
static const char *psnr_text(double psnr, double rmse, char *buf, size_t len)
{
    if (rmse == 0.0)
        snprintf(buf, len, "inf");
    else if (psnr >= C5_PSNR_CAP)
        snprintf(buf, len, ">=%g", C5_PSNR_CAP);
    else
        snprintf(buf, len, "%.2f", psnr);
    return buf;
}

static void print_text(const char *label, const compare_args *a, const c5_scene *s, int frames, int threads,
                       const compare_result *r)
{
    const c5_image_diff *d = &r->d;
    const c5_board_stats *b = &r->board;
    char p[4][32], stages[128];
    printf("cube5 compare: %s, %dx%d, frame %ld of %d\n", label, s->render.width, s->render.height, a->frame, frames);
    printf("  models    cref (%s, %d thread(s)) vs rtl (board model, cells %dx%dx%d, %s key)\n",
           a->ref_long ? "long double" : "double", threads, a->cells[0], a->cells[1], a->cells[2], c5_cli_queue_key_name(a->key));
    printf("  error     e = rtl - cref on the linear frame-buffer values; PSNR peak 1.0\n");
    printf("            %-12s %-12s %-12s %-12s\n", "all", "red", "green", "blue");
    printf("  PSNR dB   %-12s %-12s %-12s %-12s\n", psnr_text(d->psnr_db, d->rmse, p[0], sizeof p[0]),
           psnr_text(d->psnr_ch[0], d->rmse_ch[0], p[1], sizeof p[1]),
           psnr_text(d->psnr_ch[1], d->rmse_ch[1], p[2], sizeof p[2]),
           psnr_text(d->psnr_ch[2], d->rmse_ch[2], p[3], sizeof p[3]));
    printf("  RMSE      %-12.4e %-12.4e %-12.4e %-12.4e\n", d->rmse, d->rmse_ch[0], d->rmse_ch[1], d->rmse_ch[2]);
    printf("  max |e|   %-12.4e %-12.4e %-12.4e %-12.4e\n", d->max_abs_err, d->max_abs_ch[0], d->max_abs_ch[1],
           d->max_abs_ch[2]);
    printf("  |e| in 8-bit steps (1/255): %llu channel values, %llu differ\n", (unsigned long long)d->values,
           (unsigned long long)d->differing);
    for (int i = 0; i < C5_METRIC_BINS; i++)
        printf("    %-12s %12llu  %6.2f%%\n", c5_metric_bin_label(i), (unsigned long long)d->hist[i],
               100.0 * (double)d->hist[i] / (double)d->values);
    printf("  host time cref %.3f s, rtl model %.3f s\n", r->cref_wall_s, r->model_wall_s);
    printf("  board     %llu cycles (process %llu, fetch stall %llu), %.6f s at 100 MHz\n",
           (unsigned long long)b->cycles, (unsigned long long)b->cycles_process, (unsigned long long)b->cycles_fetch,
           b->board_s);
    printf("  fetches   %llu cell fetch(es), %llu bytes\n", (unsigned long long)b->fetches,
           (unsigned long long)b->fetch_bytes);
    c5_cli_stages_text(&b->stages, stages, sizeof stages);
    printf("  stages    %s\n", stages);
    if (a->bd.given)
        c5_cli_mb_print(&r->mb);
    if (a->diff)
        printf("  diff      %s (|e| x %g)\n", a->diff, a->gain);
    else
        printf("  diff      not written (give --diff OUT.png)\n");
}

static void result_free(compare_result *r)
{
    c5_image_free(&r->ref);
    c5_image_free(&r->test);
}

int c5_cmd_compare(int argc, char **argv)
{
    if (c5_opt_help(&c5_spec_compare, argc, argv))
        return 0;
    compare_args a;
    c5_err err;
    static c5_scene s;
    char label[1100];
    c5_supervol sv = {0};
    compare_result r;
    c5_progress prog = {0};
    memset(&r, 0, sizeof r);
    int rc = C5_EXIT_INPUT;
    if (parse_args(argc, argv, &a, &err) != 0 ||
        c5_cli_scene_setup(a.scene_arg, &a.volumes, a.size[0], a.size[1], &s, label, sizeof label, &err) != 0)
        goto fail;
    int frames = c5_scene_frames(&s);
    if (a.frame >= frames) {
        c5_fail(&err, "--frame: the scene has %d frame(s) (0..%d), no frame %ld", frames, frames - 1, a.frame);
        goto fail;
    }
    if (a.diff && c5_cli_check_scene_image_out(a.diff, 1, a.scene_arg, &s, &err) != 0)
        goto fail;
    if (c5_cli_model_grid(&s, a.cells, label, &sv, &err) != 0)
        goto fail;

    if (c5_boards_begin(&a.bd, &err) != 0)
        goto fail;
    rc = C5_EXIT_RUNTIME;
    c5_cref_opts copts = {.threads = (int)a.threads};
    c5_board_opts bopts = {.key = a.key};
    memcpy(bopts.cells, a.cells, sizeof bopts.cells);
    c5_progress_begin(&prog, "compare", 2);
    if (!c5_boards_leader(&a.bd))
        prog.mode = 0;
    c5_progress_frame pf = {&prog, 1, (int)a.frame};
    bopts.progress = c5_progress_board;
    bopts.progress_ctx = &pf;
    /* Several boards: the model first (every board), then cref on board 0 alone. */
    double tm = c5_now_s();
    if (a.bd.given && c5_boards_render(&a.bd, &s, &sv, (int)a.frame, &bopts, NULL, &r.test, &r.mb, &err) != 0) {
        if (a.bd.mpi)
            c5_mpi_fail(&a.bd.t, err.msg, C5_EXIT_RUNTIME);
        goto fail;
    }
    r.board = r.mb.sum;
    tm = c5_now_s() - tm;
    if (!c5_boards_leader(&a.bd)) {
        result_free(&r);
        c5_supervol_free(&sv);
        c5_boards_end(&a.bd);
        return 0;
    }
    double t0 = c5_now_s();
    if ((a.ref_long ? c5_cref_render_long : c5_cref_render)(&s, &sv, (int)a.frame, &copts, &r.ref, &r.cref, &err) !=
        0)
        goto fail;
    double t1 = c5_now_s();
    c5_progress_step(&prog, 1, "cref: %.2f s", t1 - t0);
    if (!a.bd.given && c5_board_render(&s, &sv, (int)a.frame, &bopts, &r.test, &r.board, &err) != 0)
        goto fail;
    c5_progress_step(&prog, 2, "rtl model: %.2f s", c5_now_s() - t1);
    c5_progress_end(&prog);
    r.cref_wall_s = t1 - t0;
    r.model_wall_s = a.bd.given ? tm : c5_now_s() - t1;
    if (c5_image_compare(&r.ref, &r.test, &r.d, &err) != 0)
        goto fail;
    if (a.diff) {
        c5_image diff;
        int bad = c5_image_diff_image(&r.ref, &r.test, a.gain, &diff, &err) != 0 ||
                  c5_image_write(a.diff, &diff, &err) != 0;
        c5_image_free(&diff);
        if (bad)
            goto fail;
    }
    int threads = c5_cref_thread_count((int)a.threads);
    if (a.json)
        print_json(&a, &s, threads, &r);
    else
        print_text(label, &a, &s, frames, threads, &r);
    result_free(&r);
    c5_supervol_free(&sv);
    c5_boards_end(&a.bd);
    return 0;
fail:
    c5_progress_end(&prog);
    result_free(&r);
    c5_supervol_free(&sv);
    fprintf(stderr, "cube5: error: %s\n", err.msg);
    return rc;
}
