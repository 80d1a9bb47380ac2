/* cube5 sweep: error against run time over the renderers' settings (sweep/sweep.h,
 * docs/sweep.md). Writes DIR/sweep.csv and DIR/sweep.png (gnuplot, pngcairo), progress per
 * run on stderr (cli/progress.h), and a table (or --json) on stdout. */
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>

#include "atomic_file.h"
#include "cli.h"
#include "progress.h"
#include "sweep.h"

typedef struct {
    const char *scene_arg, *out_dir;
    c5_cli_volumes volumes;
    int size[2], json;
    long threads;
    c5_sweep_knob knobs[C5_SWEEP_MAX_KNOBS];
    int n_knobs;
} sweep_args;

static int knob_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    sweep_args *a = field;
    if (a->n_knobs == C5_SWEEP_MAX_KNOBS)
        return c5_fail(err, "%s: at most %d knobs", o->name, C5_SWEEP_MAX_KNOBS);
    c5_sweep_knob *k = &a->knobs[a->n_knobs];
    if (c5_sweep_knob_parse(v, k, err) != 0)
        return -1;
    for (int j = 0; j < a->n_knobs; j++)
        if (!strcmp(a->knobs[j].name, k->name))
            return c5_fail(err, "%s %s: given twice (list all its values in one --knob)", o->name, k->name);
    a->n_knobs++;
    return 0;
}

static const c5_opt opts[] = {
    {"--knob", "NAME=V1,V2,...", knob_opt, 0, 0, 0, 0, "a knob and its values (the knobs above); once per knob"},
    {"--out", "DIR", c5_opt_str, offsetof(sweep_args, out_dir), 0, 0, 0,
     "where sweep.csv and sweep.png go (default out/sweep_SCENE)"},
    {"--size", "N|WxH", c5_opt_size, offsetof(sweep_args, size), 0, 0, 0, "image size instead of the scene's (N: NxN)"},
    {"--threads", "N", c5_opt_long, offsetof(sweep_args, threads), 1, 256, 0,
     "cref's threads and the caster's workers (default: one per CPU)"},
    {"--volume", "[I=]FILE", c5_opt_volume, offsetof(sweep_args, volumes), 0, 0, 0,
     "replace volume I (default 0) by a raw or NRRD file"},
    {"--json", NULL, c5_opt_flag, offsetof(sweep_args, json), 0, 0, 0, "one JSON object on stdout instead of the table"},
    {0},
};

const c5_cmd_spec c5_spec_sweep = {
    "sweep", "[SCENE|FILE.json]",
    "Renders a scene over a range of one setting at a time (the others at the scene's values) and puts each "
    "image's error against a converged reference (PSNR, RMSE, largest error, as cube5 compare reports them) next to "
    "its cost (host wall time; modelled board time for the board model). Writes DIR/sweep.csv and DIR/sweep.png "
    "(RMSE against time, log-log, the Pareto front drawn; needs gnuplot). Definitions and the reference: "
    "docs/sweep.md.\n\n"
    "Knobs (NAME=V1,V2,...; without --knob, each knob over a few values around the scene's, docs/sweep.md):\n\n"
    "  step=V,...        sample step in voxels (the grid's smallest spacing), (0, 7.99): cref, model\n"
    "  et=V,...          early-termination opacity, (0, 1]: cref, model\n"
    "  bounces=N,...     reflect/refract generations, 0..15: cref, model\n"
    "  width.NAME=B,...  fraction bits of a datapath signal, 1..shipped (pos, dir, value, rgba,\n"
    "                    opacity, rgb, normal): model\n"
    "  k=N,...           the streaming caster's approximation interval, 1, 2, 4, 8, 16: cast",
    {{opts, 0}, {c5_progress_opts, 0}},
};

static int parse_args(int argc, char **argv, sweep_args *a, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->scene_arg = "default";
    return c5_opt_parse(&c5_spec_sweep, argc, argv, a, &a->scene_arg, err);
}

/* One row of the sweep: a knob's value on one renderer. */
typedef struct {
    const c5_sweep_knob *knob;
    double value;
    int is_default;
    c5_sweep_renderer r;
    c5_sweep_point p;
    c5_sweep_result res;
    int same_as;            /* -1, or the row whose run this row shares (same renderer, same point) */
    int pareto_host, pareto_board;
} sweep_row;

/* The settings a renderer reads: cref ignores the widths and k, the model k, the caster
 * everything but the step and k. */
static int same_run(c5_sweep_renderer r, const c5_sweep_point *a, const c5_sweep_point *b)
{
    if (a->step != b->step)
        return 0;
    if (r == C5_SW_CAST)
        return a->k == b->k;
    if (a->et != b->et || a->bounces != b->bounces)
        return 0;
    return r == C5_SW_CREF || !memcmp(&a->widths, &b->widths, sizeof a->widths);
}

/* "gnuplot" on PATH with the pngcairo terminal. */
static int check_gnuplot(c5_err *err)
{
    int st = system("gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1");
    if (st != 0)
        return c5_fail(err, "sweep: gnuplot with the pngcairo terminal is needed to draw sweep.png and was not found "
                            "(install gnuplot-nox: bash scripts/setup-deps.sh gnuplot-nox)");
    return 0;
}

static void fmt_num(char *buf, size_t len, double v, const char *fmt)
{
    if (isnan(v))
        buf[0] = 0;
    else
        snprintf(buf, len, fmt, v);
}

static int write_csv(const char *path, const sweep_row *rows, int n, c5_err *err)
{
    c5_afile f;
    if (c5_afile_open(&f, path, err) != 0)
        return -1;
    c5_afile_printf(&f, "knob,value,default,renderer,status,psnr_db,rmse,max_abs_err,host_s,board_s,samples,"
                        "pareto_host,pareto_board\n");
    for (int i = 0; i < n; i++) {
        const sweep_row *r = &rows[i];
        char ps[32], rm[32], mx[32], hs[32], bs[32];
        fmt_num(ps, sizeof ps, r->res.psnr_db, "%.4f");
        fmt_num(rm, sizeof rm, r->res.rmse, "%.6e");
        fmt_num(mx, sizeof mx, r->res.max_abs_err, "%.6e");
        fmt_num(hs, sizeof hs, r->res.host_s, "%.6f");
        fmt_num(bs, sizeof bs, r->res.board_s, "%.6e");
        c5_afile_printf(&f, "%s,%g,%d,%s,%s,%s,%s,%s,%s,%s,%llu,%d,%d\n", r->knob->name, r->value, r->is_default,
                        c5_sweep_renderer_name(r->r), r->res.ok ? "ok" : "error", ps, rm, mx, hs, bs,
                        (unsigned long long)r->res.samples, r->pareto_host, r->pareto_board);
    }
    return c5_afile_commit(&f, err);
}

/* A gnuplot single-quoted string: ' doubled. */
static void gp_quoted(FILE *g, const char *s)
{
    fputc('\'', g);
    for (; *s; s++) {
        if (*s == '\'')
            fputc('\'', g);
        fputc(*s, g);
    }
    fputc('\'', g);
}

/* Log axes: a zero error (identical images) or time is drawn at a floor. */
static double gp_pos(double v, double floor_v) { return v > floor_v ? v : floor_v; }

/* The x of a row in panel `board` (0: host time, all rows; 1: board time, model rows). */
static double row_x(const sweep_row *r, int board) { return board ? r->res.board_s : r->res.host_s; }
static int row_in(const sweep_row *r, int board) { return r->res.ok && (!board || r->r == C5_SW_MODEL); }

static const int point_types[] = {7, 5, 9, 11, 13, 15, 4, 6, 8, 10, 12, 14, 1, 2, 3};
static const char *const renderer_colour[] = {"#1f5fbf", "#d62728", "#2ca02c"};

static void gp_panel(FILE *g, const sweep_row *rows, int n, const sweep_args *a, int board)
{
    /* Data blocks: one per knob and renderer, the default points, the front sorted by x. */
    int n_series = 0, has_default = 0;
    for (int k = 0; k < a->n_knobs; k++)
        for (int rr = 0; rr < 3; rr++) {
            int any = 0;
            for (int i = 0; i < n; i++)
                if (rows[i].knob == &a->knobs[k] && rows[i].r == (c5_sweep_renderer)rr && row_in(&rows[i], board)) {
                    if (!any)
                        fprintf(g, "$s%d_%d_%d << EOD\n", board, k, rr);
                    any = 1;
                    fprintf(g, "%.9g %.9g\n", gp_pos(row_x(&rows[i], board), 1e-9), gp_pos(rows[i].res.rmse, 1e-10));
                }
            if (any) {
                fprintf(g, "EOD\n");
                n_series++;
            }
        }
    fprintf(g, "$def%d << EOD\n", board);
    for (int i = 0; i < n; i++)
        if (rows[i].is_default && row_in(&rows[i], board)) {
            fprintf(g, "%.9g %.9g\n", gp_pos(row_x(&rows[i], board), 1e-9), gp_pos(rows[i].res.rmse, 1e-10));
            has_default = 1;
        }
    fprintf(g, "EOD\n");
    /* The fronts' points by rising x (selection sort: a few dozen rows); group 0 the rows
     * against cref's reference, 1 the caster's. */
    int has_front[2] = {0, 0};
    for (int grp = 0; grp < 2; grp++) {
        fprintf(g, "$front%d_%d << EOD\n", board, grp);
        int used[4096] = {0};
        for (;;) {
            int best = -1;
            for (int i = 0; i < n && i < 4096; i++) {
                int on = (board ? rows[i].pareto_board : rows[i].pareto_host) && (rows[i].r == C5_SW_CAST) == grp;
                if (on && !used[i] && (best < 0 || row_x(&rows[i], board) < row_x(&rows[best], board)))
                    best = i;
            }
            if (best < 0)
                break;
            used[best] = 1;
            has_front[grp] = 1;
            fprintf(g, "%.9g %.9g\n", gp_pos(row_x(&rows[best], board), 1e-9), gp_pos(rows[best].res.rmse, 1e-10));
        }
        fprintf(g, "EOD\n");
    }
    fprintf(g, "set xlabel '%s'\n", board ? "modelled board time (s, 100 MHz)" : "host wall time (s)");
    fprintf(g, "set title '%s'\n",
            board ? "board model: error against modelled board time" : "error against host wall time");
    if (!n_series) {
        fprintf(g, "unset logscale xy\nset xrange [0:1]\nset yrange [0:1]\n"
                   "set label 1 'no rows' at 0.5,0.5 center\nplot NaN notitle\nunset label 1\n"
                   "set autoscale xy\nset logscale xy\n");
        return;
    }
    /* An axis whose points all sit at one value gets a decade around it (gnuplot would warn
     * "empty x range" on stderr of a run that went well). */
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {0, 0};
    for (int i = 0; i < n; i++)
        if (row_in(&rows[i], board)) {
            double v[2] = {gp_pos(row_x(&rows[i], board), 1e-9), gp_pos(rows[i].res.rmse, 1e-10)};
            for (int ax = 0; ax < 2; ax++)
                lo[ax] = fmin(lo[ax], v[ax]), hi[ax] = fmax(hi[ax], v[ax]);
        }
    for (int ax = 0; ax < 2; ax++)
        if (lo[ax] == hi[ax])
            fprintf(g, "set %crange [%.9g:%.9g]\n", "xy"[ax], lo[ax] / sqrt(10.0), lo[ax] * sqrt(10.0));
        else
            fprintf(g, "set autoscale %c\n", "xy"[ax]);
    fprintf(g, "plot ");
    const char *sep = "";
    for (int k = 0; k < a->n_knobs; k++)
        for (int rr = 0; rr < 3; rr++) {
            int any = 0;
            for (int i = 0; i < n; i++)
                any |= rows[i].knob == &a->knobs[k] && rows[i].r == (c5_sweep_renderer)rr && row_in(&rows[i], board);
            if (!any)
                continue;
            fprintf(g, "%s$s%d_%d_%d using 1:2 with points pt %d ps 1.4 lc rgb '%s' title '%s (%s)'", sep, board, k,
                    rr, point_types[k % (int)(sizeof point_types / sizeof point_types[0])], renderer_colour[rr],
                    a->knobs[k].name, c5_sweep_renderer_name((c5_sweep_renderer)rr));
            sep = ", \\\n     ";
        }
    if (has_front[0])
        fprintf(g, "%s$front%d_0 using 1:2 with lines lw 2 dt 2 lc rgb '#000000' title 'Pareto front%s'", sep, board,
                has_front[1] ? " (cref reference)" : "");
    if (has_front[1])
        fprintf(g, "%s$front%d_1 using 1:2 with lines lw 2 dt 3 lc rgb '#2ca02c' title 'Pareto front%s'", sep, board,
                has_front[0] ? " (cast reference)" : "");
    if (has_default)
        fprintf(g, "%s$def%d using 1:2 with points pt 6 ps 3 lw 1.5 lc rgb '#000000' title 'default / shipped'", sep,
                board);
    fprintf(g, "\n");
}

/* gnuplot draws into a temporary beside `path`, which is read back whole (gnuplot's own
 * write errors do not always reach its exit status) before it is renamed into place. */
static int write_png(const char *path, const char *label, int w, int h, const sweep_row *rows, int n,
                     const sweep_args *a, c5_err *err)
{
    char tmp[4200];
    c5_afile_tmp_path(path, ".png", tmp, sizeof tmp); /* gnuplot picks the format from the name */
    FILE *g = popen("gnuplot", "w");
    if (!g)
        return c5_fail(err, "sweep: cannot start gnuplot: %s", strerror(errno));
    fprintf(g, "set terminal pngcairo size 1400,620 font 'sans,10'\nset output ");
    gp_quoted(g, tmp);
    fprintf(g, "\nset logscale xy\nset grid\nset format x '%%g'\nset format y '%%.0e'\n"
               "set ylabel 'RMSE against the reference (peak 1.0)'\nset key outside right top box font ',9'\n"
               "set multiplot layout 1,2 title ");
    char title[1400];
    snprintf(title, sizeof title, "cube5 sweep: %s, %dx%d", label, w, h);
    for (char *p = title; *p; p++)
        if (*p == '_')
            *p = ' '; /* gnuplot's enhanced text would subscript */
    gp_quoted(g, title);
    fprintf(g, "\n");
    gp_panel(g, rows, n, a, 0);
    gp_panel(g, rows, n, a, 1);
    fprintf(g, "unset multiplot\nset output\n");
    int st = pclose(g);
    c5_image check = {0};
    c5_err why;
    int rc = 0;
    if (st != 0)
        rc = c5_fail(err, "%s: gnuplot failed (status %d)", path, st);
    else if (c5_image_read(tmp, &check, &why) != 0)
        rc = c5_fail(err, "%s: cannot write: gnuplot's image is not whole (%s)", path, why.msg);
    else if (rename(tmp, path) != 0)
        rc = c5_fail(err, "%s: cannot write: %s", path, strerror(errno));
    c5_image_free(&check);
    if (rc)
        unlink(tmp);
    return rc;
}

static json_t *num_or_null(double v) { return isnan(v) ? json_null() : json_real(v); }

static json_t *diff_json(const c5_image_diff *d)
{
    return json_pack("{s:o, s:o, s:o}", "psnr_db", json_real(d->psnr_db), "rmse", json_real(d->rmse),
                     "max_abs_err", json_real(d->max_abs_err));
}

static void print_json(const char *label, const c5_scene *s, const c5_sweep_ctx *c, const sweep_row *rows, int n,
                       const char *csv, const char *png)
{
    json_t *o = json_object(), *jr = json_array(), *ph = json_array(), *pb = json_array();
    json_object_set_new(o, "scene", json_string(s->name));
    json_object_set_new(o, "label", json_string(label));
    json_object_set_new(o, "size", json_pack("[i, i]", s->render.width, s->render.height));
    json_t *w = json_object();
    for (int i = 0; i < C5_W_COUNT; i++)
        json_object_set_new(w, c5_width_name((c5_width_id)i), json_integer(c->base.widths.frac[i]));
    json_object_set_new(o, "defaults",
                        json_pack("{s:f, s:f, s:i, s:o, s:o}", "step", c->base.step, "et", c->base.et, "bounces",
                                  c->base.bounces, "widths", w,
                                  "k", c->cast_ready ? json_integer(c->base.k) : json_null()));
    json_t *ref = json_pack("{s:s, s:s, s:f, s:f, s:i, s:f, s:{s:f, s:f, s:o}}", "renderer", "cref", "field",
                            c->analytic ? "analytic Marschner-Lobb" : "voxels", "step", c->ref_step, "et", c->ref_et,
                            "bounces", c->ref_bounces, "wall_s", c->ref_wall_s, "convergence", "coarse_step",
                            c->ref_coarse_step, "step", c->ref_step, "diff", diff_json(&c->ref_conv));
    if (c->cast_ready) {
        int exact = 1, any = 0;
        for (int i = 0; i < n; i++)
            if (rows[i].r == C5_SW_CAST && rows[i].res.identical_to_plain >= 0)
                exact &= rows[i].res.identical_to_plain, any = 1;
        json_object_set_new(ref, "cast",
                            json_pack("{s:s, s:f, s:b, s:{s:f, s:f, s:o}, s:o}", "mode", "plain", "step",
                                      c->cast_ref_step, "early_termination", 0, "convergence", "coarse_step",
                                      2 * c->cast_ref_step, "step", c->cast_ref_step, "diff", diff_json(&c->cast_conv),
                                      "rows_identical_to_plain", any ? json_boolean(exact) : json_null()));
    } else
        json_object_set_new(ref, "cast", json_null());
    json_object_set_new(o, "reference", ref);
    for (int i = 0; i < n; i++) {
        const sweep_row *r = &rows[i];
        json_t *row = json_object();
        json_object_set_new(row, "knob", json_string(r->knob->name));
        json_object_set_new(row, "value", json_real(r->value));
        json_object_set_new(row, "default", json_boolean(r->is_default));
        json_object_set_new(row, "renderer", json_string(c5_sweep_renderer_name(r->r)));
        json_object_set_new(row, "status", json_string(r->res.ok ? "ok" : "error"));
        json_object_set_new(row, "message", r->res.ok ? json_null() : json_string(r->res.msg));
        json_object_set_new(row, "psnr_db", num_or_null(r->res.psnr_db));
        json_object_set_new(row, "rmse", num_or_null(r->res.rmse));
        json_object_set_new(row, "max_abs_err", num_or_null(r->res.max_abs_err));
        json_object_set_new(row, "host_s", num_or_null(r->res.host_s));
        json_object_set_new(row, "board_s", num_or_null(r->res.board_s));
        json_object_set_new(row, "samples", json_integer((json_int_t)r->res.samples));
        json_object_set_new(row, "same_as", r->same_as >= 0 ? json_integer(r->same_as) : json_null());
        json_object_set_new(row, "pareto_host", json_boolean(r->pareto_host));
        json_object_set_new(row, "pareto_board", json_boolean(r->pareto_board));
        if (r->r == C5_SW_CAST)
            json_object_set_new(row, "identical_to_plain",
                                r->res.identical_to_plain < 0 ? json_null() : json_boolean(r->res.identical_to_plain));
        json_array_append_new(jr, row);
        if (r->pareto_host)
            json_array_append_new(ph, json_integer(i));
        if (r->pareto_board)
            json_array_append_new(pb, json_integer(i));
    }
    json_object_set_new(o, "rows", jr);
    json_object_set_new(o, "pareto_host", ph);
    json_object_set_new(o, "pareto_board", pb);
    json_object_set_new(o, "csv", json_string(csv));
    json_object_set_new(o, "png", json_string(png));
    json_object_set_new(o, "outputs", json_pack("[s, s]", csv, png));
    char *text = json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(9));
    puts(text);
    free(text);
    json_decref(o);
}

static void print_text(const char *label, const c5_scene *s, const c5_sweep_ctx *c, const sweep_row *rows, int n,
                       const char *csv, const char *png)
{
    printf("cube5 sweep: %s, %dx%d\n", label, s->render.width, s->render.height);
    printf("  reference  %s, step %g voxels, et 1, %d bounces (%.2f s)\n",
           c->analytic ? "cref on the analytic Marschner-Lobb signal" : "cref", c->ref_step, c->ref_bounces,
           c->ref_wall_s);
    printf("  converged  step %g against %g: RMSE %.3e, PSNR %.2f dB, max |e| %.3e\n", c->ref_coarse_step,
           c->ref_step, c->ref_conv.rmse, c->ref_conv.psnr_db, c->ref_conv.max_abs_err);
    if (c->cast_ready)
        printf("  cast ref   plain, step %g voxels, no early termination; step %g against it: RMSE %.3e\n",
               c->cast_ref_step, 2 * c->cast_ref_step, c->cast_conv.rmse);
    printf("  %-14s %8s %3s %-6s %9s %11s %11s %10s %11s %11s %2s\n", "knob", "value", "def", "render", "PSNR dB",
           "RMSE", "max |e|", "host s", "board s", "samples", "P");
    for (int i = 0; i < n; i++) {
        const sweep_row *r = &rows[i];
        if (!r->res.ok) {
            printf("  %-14s %8g %3s %-6s %s\n", r->knob->name, r->value, r->is_default ? "*" : "",
                   c5_sweep_renderer_name(r->r), r->res.msg);
            continue;
        }
        char bs[32];
        fmt_num(bs, sizeof bs, r->res.board_s, "%.4e");
        printf("  %-14s %8g %3s %-6s %9.2f %11.4e %11.4e %10.4f %11s %11llu %2s\n", r->knob->name, r->value,
               r->is_default ? "*" : "", c5_sweep_renderer_name(r->r), r->res.psnr_db, r->res.rmse,
               r->res.max_abs_err, r->res.host_s, bs, (unsigned long long)r->res.samples,
               r->pareto_host && r->pareto_board ? "HB" : r->pareto_host ? "H" : r->pareto_board ? "B" : "");
    }
    printf("  (* the scene's setting or the shipped width; P: on the Pareto front of host time H, board time B)\n");
    printf("  wrote %s and %s\n", csv, png);
}

/* Progress over the reference renders and then the rows, numbered together. */
typedef struct {
    c5_progress p;
    int done;
} sweep_progress;

static void ref_progress(void *arg, const char *what, double s)
{
    sweep_progress *sp = arg;
    c5_progress_step(&sp->p, ++sp->done, "%s: %.2f s", what, s);
}

/* DIR (--out, or out/sweep_SCENE), its sweep.csv and sweep.png; neither may be a file the
 * scene reads. 0, or -1 with err. */
static int out_paths(const sweep_args *a, const c5_scene *s, char *dir, size_t dir_len, char *csv, char *png,
                     size_t len, c5_err *err)
{
    if (a->out_dir)
        snprintf(dir, dir_len, "%s", a->out_dir);
    else {
        char name[130];
        snprintf(name, sizeof name, "%s", s->name[0] ? s->name : "scene");
        for (char *p = name; *p; p++)
            if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '-'))
                *p = '_';
        snprintf(dir, dir_len, "out/sweep_%s", name);
    }
    snprintf(csv, len, "%s/sweep.csv", dir);
    snprintf(png, len, "%s/sweep.png", dir);
    const char *outs[2] = {csv, png};
    c5_file_list in = {0};
    int refused = c5_cli_scene_inputs(a->scene_arg, s, &in, err);
    for (int i = 0; i < 2 && !refused; i++)
        refused = c5_cli_check_not_input(outs[i], &in, err);
    c5_file_list_free(&in);
    return refused ? -1 : 0;
}

/* Every knob's value on each of its renderers into rows[0..n-1]; a row with the run of an
 * earlier row (same renderer, same point) shares its result. 0, or -1 with err. */
static int run_rows(c5_sweep_ctx *ctx, const sweep_args *a, sweep_row *rows, sweep_progress *prog, c5_err *err)
{
    int at = 0;
    for (int k = 0; k < a->n_knobs; k++) {
        const c5_sweep_knob *kn = &a->knobs[k];
        c5_sweep_renderer rs[2];
        int nr = c5_sweep_knob_renderers(kn, rs);
        for (int i = 0; i < kn->n; i++)
            for (int j = 0; j < nr; j++) {
                sweep_row *r = &rows[at];
                r->knob = kn;
                r->value = kn->v[i];
                r->is_default = c5_sweep_is_default(&ctx->base, kn, kn->v[i]);
                r->r = rs[j];
                r->p = c5_sweep_point_with(&ctx->base, kn, kn->v[i]);
                r->same_as = -1;
                for (int q = 0; q < at && r->same_as < 0; q++)
                    if (rows[q].r == r->r && rows[q].same_as < 0 && same_run(r->r, &rows[q].p, &r->p))
                        r->same_as = q;
                if (r->same_as >= 0)
                    r->res = rows[r->same_as].res;
                else if (c5_sweep_run(ctx, r->r, &r->p, &r->res, err) != 0)
                    return -1;
                const char *rn = c5_sweep_renderer_name(r->r);
                if (!r->res.ok)
                    c5_progress_step(&prog->p, ++prog->done, "%s=%g %s: refused: %s", kn->name, kn->v[i], rn,
                                     r->res.msg);
                else if (r->same_as >= 0)
                    c5_progress_step(&prog->p, ++prog->done, "%s=%g %s: %.2f s, RMSE %.3e (the run of row %d)",
                                     kn->name, kn->v[i], rn, r->res.host_s, r->res.rmse, r->same_as + 1);
                else
                    c5_progress_step(&prog->p, ++prog->done, "%s=%g %s: %.2f s, RMSE %.3e", kn->name, kn->v[i], rn,
                                     r->res.host_s, r->res.rmse);
                at++;
            }
    }
    return 0;
}

/* The Pareto fronts among rows measured against the same reference: cref's (cref and model
 * rows) and the caster's (cast rows); the board-time front has model rows only. 0, or -1. */
static int mark_pareto(sweep_row *rows, int n, c5_err *err)
{
    double *t = malloc(sizeof(double) * 2 * (size_t)n), *e = malloc(sizeof(double) * (size_t)n);
    int *on = malloc(sizeof(int) * (size_t)n);
    if (!t || !e || !on) {
        free(t), free(e), free(on);
        return c5_fail(err, "out of memory");
    }
    for (int pass = 0; pass < 3; pass++) {
        int board = pass == 2;
        for (int i = 0; i < n; i++) {
            int in = row_in(&rows[i], board) && (board || (rows[i].r == C5_SW_CAST) == (pass == 1));
            t[i] = in ? row_x(&rows[i], board) : NAN;
            e[i] = in ? rows[i].res.rmse : NAN;
        }
        c5_sweep_pareto(t, e, n, on);
        for (int i = 0; i < n; i++)
            if (on[i])
                *(board ? &rows[i].pareto_board : &rows[i].pareto_host) = 1;
    }
    free(t), free(e), free(on);
    return 0;
}

int c5_cmd_sweep(int argc, char **argv)
{
    if (c5_opt_help(&c5_spec_sweep, argc, argv))
        return 0;
    static sweep_args a;
    static c5_scene s;
    c5_err err;
    char label[1100], dir[2048], csv[2200], png[2200];
    c5_supervol sv = {0};
    c5_sweep_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    sweep_row *rows = NULL;
    sweep_progress prog = {{0}, 0};
    int rc = C5_EXIT_INPUT;
    if (parse_args(argc, argv, &a, &err) != 0 ||
        c5_cli_scene_setup(a.scene_arg, &a.volumes, a.size[0], a.size[1], &s, label, sizeof label, &err) != 0)
        goto fail;
    if (out_paths(&a, &s, dir, sizeof dir, csv, png, sizeof csv, &err) != 0)
        goto fail;
    if (c5_model_check_scene(&s, NULL, label, &err) != 0 || c5_cli_grid(&s, label, &sv, &err) != 0)
        goto fail;
    if (!a.n_knobs) {
        c5_sweep_point base;
        c5_sweep_ctx probe;
        if (c5_sweep_init(&probe, &s, &sv, 1, 0, &err) != 0)
            goto fail;
        base = probe.base;
        c5_sweep_free(&probe);
        a.n_knobs = c5_sweep_default_knobs(&base, !c5_supervol_empty(&sv), a.knobs);
    }
    int need_cast = 0, n = 0;
    double finest = INFINITY;
    for (int k = 0; k < a.n_knobs; k++) {
        c5_sweep_renderer r[2];
        need_cast |= a.knobs[k].kind == C5_KNOB_K;
        n += a.knobs[k].n * c5_sweep_knob_renderers(&a.knobs[k], r);
        if (a.knobs[k].kind == C5_KNOB_STEP)
            for (int i = 0; i < a.knobs[k].n; i++)
                finest = fmin(finest, a.knobs[k].v[i]);
    }
    if (need_cast && c5_supervol_empty(&sv)) {
        c5_fail(&err, "--knob k: the scene has no volume to cast");
        goto fail;
    }
    if (check_gnuplot(&err) != 0) {
        rc = C5_EXIT_RUNTIME;
        goto fail;
    }
    if (c5_output_dir(dir, &err) != 0)
        goto fail;
    rc = C5_EXIT_RUNTIME;
    if (c5_sweep_init(&ctx, &s, &sv, (int)a.threads, need_cast, &err) != 0)
        goto fail;
    c5_progress_begin(&prog.p, "sweep", c5_sweep_reference_steps(&ctx) + n);
    if (c5_sweep_reference(&ctx, finest, ref_progress, &prog, &err) != 0)
        goto fail;
    rows = calloc((size_t)n, sizeof *rows);
    if (!rows) {
        c5_fail(&err, "out of memory");
        goto fail;
    }
    if (run_rows(&ctx, &a, rows, &prog, &err) != 0 || mark_pareto(rows, n, &err) != 0)
        goto fail;
    c5_progress_end(&prog.p);
    if (write_csv(csv, rows, n, &err) != 0 || write_png(png, label, s.render.width, s.render.height, rows, n, &a, &err))
        goto fail;
    if (a.json)
        print_json(label, &s, &ctx, rows, n, csv, png);
    else
        print_text(label, &s, &ctx, rows, n, csv, png);
    free(rows);
    c5_sweep_free(&ctx);
    c5_supervol_free(&sv);
    return 0;
fail:
    c5_progress_end(&prog.p);
    free(rows);
    c5_sweep_free(&ctx);
    c5_supervol_free(&sv);
    fprintf(stderr, "cube5: error: %s\n", err.msg);
    return rc;
}
