/* cube5 compare: one frame through cref and through the board model, the difference
 * (docs/compare.md) and the cost of each, on stdout (text or --json). */
#include <jansson.h>
#include <math.h>
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

static const char usage_text[] =
    "usage: cube5 compare [SCENE|FILE.json] [--cells N|NxMxK] [--queue-key morton|fifo]\n"
    "                     [--size N|WxH] [--frame I] [--diff OUT.png] [--gain G] [--json]\n"
    "                     [--volume [I=]FILE] [--threads N] [--ref-precision double|long]\n"
    "                     [--boards N] [--assign kd|slab|mod|tree] [--link-bw MB/S]\n"
    "                     [--link-latency US] [--progress]\n\n"
    "Renders one frame of a scene (default: 'default') with cref, the reference, and with the\n"
    "bit-accurate board model, then prints how far the model's image is from cref's (PSNR,\n"
    "RMSE, largest error, overall and per channel, and a histogram of the errors in 8-bit\n"
    "steps) and what each cost. Definitions: docs/compare.md.\n\n"
    "  --cells N|NxMxK   split the grid into NxNxN (or NxMxK) cells for the model (default 1,\n"
    "                    or the fewest that keep a cell within 256 voxels a side)\n"
    "  --queue-key K     morton (default) or fifo order of the model's ray queue\n"
    "  --size N|WxH      image size instead of the scene's (N: NxN)\n"
    "  --frame I         frame I (from 0) of the scene's camera path (default 0)\n"
    "  --diff OUT        write |model - cref| x G as an image: .png (clamped) or .exr (float)\n"
    "  --gain G          G for --diff (default 16: one 8-bit step shows as 16)\n"
    "  --json            print one JSON object instead of the text\n"
    "  --volume [I=]FILE replace volume I (default 0) by a raw or NRRD file\n"
    "  --threads N       cref's worker threads (default: one per CPU); the model uses one\n"
    "  --ref-precision P cref in double (default) or long (long double; docs/stability.md)\n"
    C5_BOARDS_HELP C5_PROGRESS_HELP;

typedef struct {
    const char *scene_arg, *diff;
    long threads, frame;
    int w, h, json, ref_long;
    double gain;
    const char *volumes[C5_MAX_VOLUMES];
    int n_volumes;
    int cells[3];
    c5_queue_key key;
    c5_boards_args bd;
} compare_args;

static int parse_args(int argc, char **argv, compare_args *a, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->scene_arg = "default";
    a->gain = C5_DIFF_GAIN;
    a->cells[0] = a->cells[1] = a->cells[2] = 0; /* the automatic split */
    a->key = C5_KEY_MORTON;
    int have_scene = 0;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        int bo = c5_boards_option(argc, argv, &i, &a->bd, err);
        if (bo < 0)
            return -1;
        if (bo)
            continue;
        if (!strcmp(o, "--cells") || !strcmp(o, "--queue-key") || !strcmp(o, "--size") || !strcmp(o, "--frame") ||
            !strcmp(o, "--diff") || !strcmp(o, "--gain") || !strcmp(o, "--volume") || !strcmp(o, "--threads") ||
            !strcmp(o, "--ref-precision")) {
            if (i + 1 >= argc)
                return c5_fail(err, "%s: missing value", o);
            const char *v = argv[++i];
            if (!strcmp(o, "--cells") && c5_cli_cells(o, v, a->cells, err))
                return -1;
            else if (!strcmp(o, "--queue-key") && c5_cli_queue_key(o, v, &a->key, err))
                return -1;
            else if (!strcmp(o, "--size") && c5_cli_size(o, v, &a->w, &a->h, err))
                return -1;
            else if (!strcmp(o, "--frame") && c5_cli_int(o, v, 0, C5_MAX_FRAMES - 1, &a->frame, err))
                return -1;
            /* 1e-6..1e6: at 1e6 an error of 1e-6 is white already; below 1e-6 no error in [0,1] shows. */
            else if (!strcmp(o, "--gain") && c5_cli_double(o, v, 1e-6, 1e6, &a->gain, err))
                return -1;
            else if (!strcmp(o, "--threads") && c5_cli_int(o, v, 1, 256, &a->threads, err))
                return -1;
            else if (!strcmp(o, "--diff"))
                a->diff = v;
            else if (!strcmp(o, "--ref-precision")) {
                if (strcmp(v, "double") && strcmp(v, "long"))
                    return c5_fail(err, "%s: '%s' is not double or long", o, v);
                a->ref_long = !strcmp(v, "long");
            }
            else if (!strcmp(o, "--volume")) {
                if (c5_cli_add_volume(v, a->volumes, &a->n_volumes, err) != 0)
                    return -1;
            }
        } else if (!strcmp(o, "--json")) {
            a->json = 1;
        } else if (c5_cli_scene_arg("compare", o, &a->scene_arg, &have_scene, err) != 0) {
            return -1;
        }
    }
    return 0;
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
    if (c5_cli_help(argc, argv, usage_text))
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
        c5_cli_scene_setup(a.scene_arg, a.volumes, a.n_volumes, a.w, a.h, &s, label, sizeof label, &err) != 0)
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
    if (a.bd.given && c5_mb_render(&s, &sv, (int)a.frame, &bopts, &a.bd.mo, &a.bd.t, &r.test, &r.mb, &err) != 0) {
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
