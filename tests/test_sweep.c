/* The sweep's pure parts (sweep/sweep.h, docs/sweep.md): knob parsing, the default sweep,
 * the Pareto front; and that cref's error against the sweep's reference falls with the step,
 * on voxels and against the analytic Marschner-Lobb truth. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "sweep.h"

TEST(sweep_knob_parse_values)
{
    c5_sweep_knob k;
    c5_err err;
    CHECK(c5_sweep_knob_parse("step=0.5,1,2.5", &k, &err) == 0);
    CHECK(k.kind == C5_KNOB_STEP && !strcmp(k.name, "step"));
    CHECK_INT(k.n, 3);
    CHECK(k.v[0] == 0.5 && k.v[1] == 1 && k.v[2] == 2.5);
    CHECK(c5_sweep_knob_parse("et=1", &k, &err) == 0);
    CHECK(k.kind == C5_KNOB_ET && k.n == 1 && k.v[0] == 1);
    CHECK(c5_sweep_knob_parse("bounces=0,15", &k, &err) == 0);
    CHECK(k.kind == C5_KNOB_BOUNCES && k.n == 2 && k.v[1] == 15);
    CHECK(c5_sweep_knob_parse("k=1,2,4,8,16", &k, &err) == 0);
    CHECK(k.kind == C5_KNOB_K && k.n == 5);
    CHECK(c5_sweep_knob_parse("width.rgb=1,12", &k, &err) == 0);
    CHECK(k.kind == C5_KNOB_WIDTH && k.width == C5_W_RGB && k.n == 2 && k.v[1] == 12);
    for (int i = 0; i < C5_W_COUNT; i++) {
        char spec[64];
        snprintf(spec, sizeof spec, "width.%s=%d", c5_width_name((c5_width_id)i), c5_width_shipped((c5_width_id)i));
        CHECK_MSG(c5_sweep_knob_parse(spec, &k, &err) == 0, "%s: %s", spec, err.msg);
        CHECK_INT(k.width, i);
    }
}

TEST(sweep_knob_parse_errors)
{
    static const struct {
        const char *spec, *msg;
    } bad[] = {
        {"step", "expected NAME=V1,V2"},
        {"=1", "expected NAME=V1,V2"},
        {"speed=1", "unknown knob 'speed'"},
        {"step=", "no values"},
        {"step=1,,2", "empty value"},
        {"step=1,", "empty value"},
        {"step=abc", "expected a step in voxels"},
        {"step=0", "expected a step in voxels"},
        {"step=-1", "expected a step in voxels"},
        {"step=8", "expected a step in voxels"},
        {"step=nan", "expected a step in voxels"},
        {"et=0", "expected an opacity in (0, 1]"},
        {"et=1.01", "expected an opacity in (0, 1]"},
        {"et=0.5x", "expected an opacity in (0, 1]"},
        {"bounces=16", "0..15"},
        {"bounces=1.5", "0..15"},
        {"bounces=-1", "0..15"},
        {"width.pos=16", "must be 1 .. 15"},
        {"width.pos=0", "must be 1 .. 15"},
        {"width.pos=2.5", "whole number of fraction bits"},
        {"width.foo=3", "unknown datapath width 'foo'"},
        {"k=3", "expected 1, 2, 4, 8 or 16"},
        {"k=32", "expected 1, 2, 4, 8 or 16"},
        {"et=0.9,0.9", "given twice"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        c5_sweep_knob k;
        c5_err err;
        CHECK_MSG(c5_sweep_knob_parse(bad[i].spec, &k, &err) != 0, "'%s' accepted", bad[i].spec);
        CHECK_MSG(strstr(err.msg, bad[i].msg), "'%s': message '%s' lacks '%s'", bad[i].spec, err.msg, bad[i].msg);
    }
}

TEST(sweep_default_knobs_hold_the_defaults)
{
    c5_sweep_point base = {.step = 1, .et = 0.95, .bounces = 3, .widths = c5_widths_shipped(), .k = 4};
    c5_sweep_knob k[C5_SWEEP_MAX_KNOBS];
    int n = c5_sweep_default_knobs(&base, 1, k);
    CHECK_INT(n, 4 + C5_W_COUNT);
    for (int i = 0; i < n; i++) {
        int defaults = 0;
        CHECK_MSG(k[i].n >= 3, "%s: %d values", k[i].name, k[i].n);
        for (int j = 0; j < k[i].n; j++) {
            defaults += c5_sweep_is_default(&base, &k[i], k[i].v[j]);
            if (j)
                CHECK_MSG(k[i].v[j] > k[i].v[j - 1], "%s: values not rising", k[i].name);
            /* every default value passes the parser's checks */
            char spec[96];
            snprintf(spec, sizeof spec, "%.23s=%.17g", k[i].name, k[i].v[j]);
            c5_sweep_knob p;
            c5_err err;
            CHECK_MSG(c5_sweep_knob_parse(spec, &p, &err) == 0, "%s: %s", spec, err.msg);
        }
        CHECK_MSG(defaults == 1, "%s: %d default values", k[i].name, defaults);
    }
    /* without a volume: no step and no k */
    n = c5_sweep_default_knobs(&base, 0, k);
    CHECK_INT(n, 2 + C5_W_COUNT);
    for (int i = 0; i < n; i++)
        CHECK(k[i].kind != C5_KNOB_STEP && k[i].kind != C5_KNOB_K);
    /* a point with one knob changed */
    c5_sweep_knob w;
    c5_err err;
    CHECK(c5_sweep_knob_parse("width.dir=7", &w, &err) == 0);
    c5_sweep_point p = c5_sweep_point_with(&base, &w, 7);
    CHECK_INT(p.widths.frac[C5_W_DIR], 7);
    CHECK(p.step == 1 && p.et == 0.95 && p.bounces == 3 && p.k == 4);
    CHECK(!c5_sweep_is_default(&base, &w, 7));
    CHECK(c5_sweep_is_default(&base, &w, c5_width_shipped(C5_W_DIR)));
}

TEST(sweep_pareto_front)
{
    /* (time, error): 0 fast and bad, 1 dominated by 2, 2 on the front, 3 slow and best,
     * 4 equal to 2 (ties do not dominate), 5 same time as 3 but worse, 6 same error as 0 but
     * slower, 7 NaN (never on it), 8 same error as 3 and faster: 3 falls off. */
    const double t[] = {1, 3, 2, 10, 2, 10, 1.5, NAN, 8};
    const double e[] = {0.5, 0.4, 0.2, 0.01, 0.2, 0.02, 0.5, 0.001, 0.01};
    const int want[] = {1, 0, 1, 0, 1, 0, 0, 0, 1};
    int on[9];
    c5_sweep_pareto(t, e, 9, on);
    for (int i = 0; i < 9; i++)
        CHECK_MSG(on[i] == want[i], "point %d: on %d, expected %d", i, on[i], want[i]);
    /* one point; all equal; empty */
    c5_sweep_pareto(t, e, 1, on);
    CHECK_INT(on[0], 1);
    const double same[] = {1, 1, 1};
    c5_sweep_pareto(same, same, 3, on);
    CHECK(on[0] && on[1] && on[2]);
    c5_sweep_pareto(t, e, 0, on);
    /* a NaN error alone */
    const double tn[] = {1, 2}, en[] = {NAN, 5};
    c5_sweep_pareto(tn, en, 2, on);
    CHECK(!on[0] && on[1]);
}

/* cref's RMSE against the sweep's reference at steps 2, 1, 1/2 voxel: must fall each time. */
static void error_falls(const char *json, const char *what)
{
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    c5_sweep_ctx c;
    CHECK_MSG(c5_scene_parse(c5t_json(json), NULL, what, &s, &err) == 0, "%s", err.msg);
    CHECK_MSG(c5_supervol_build(&s, &sv, &err) == 0, "%s", err.msg);
    CHECK_MSG(c5_sweep_init(&c, &s, &sv, 2, 1, &err) == 0, "%s", err.msg);
    CHECK_MSG(c5_sweep_reference(&c, 0.5, NULL, NULL, &err) == 0, "%s", err.msg);
    CHECK(c.ref_step == 0.5 / C5_SWEEP_REF_DIV && c.ref_coarse_step == 2 * c.ref_step);
    const double steps[] = {2, 1, 0.5};
    double prev = INFINITY;
    for (int i = 0; i < 3; i++) {
        c5_sweep_point p = c.base;
        p.step = steps[i];
        c5_sweep_result r;
        CHECK(c5_sweep_run(&c, C5_SW_CREF, &p, &r, &err) == 0);
        CHECK_MSG(r.ok, "%s", r.msg);
        printf("    %s: step %g voxel, RMSE %.3e against the reference\n", what, steps[i], r.rmse);
        CHECK_MSG(r.rmse < prev, "%s: step %g gives RMSE %g, the step before %g", what, steps[i], r.rmse, prev);
        prev = r.rmse;
        if (i == 2) /* the finest row is still well above the reference's own error */
            CHECK_MSG(c.ref_conv.rmse < r.rmse, "%s: reference converged to %g, finest row %g", what,
                      c.ref_conv.rmse, r.rmse);
    }
    /* a datapath width reaches the model: 3 fraction bits of pos cost error the shipped 15 do
     * not (on the blobs scene more than twice the RMSE; on Marschner-Lobb, where the voxel
     * grid's reconstruction error dominates, about 10 % more) */
    c5_sweep_knob wk;
    CHECK(c5_sweep_knob_parse("width.pos=3", &wk, &err) == 0);
    c5_sweep_result shipped, narrow;
    CHECK(c5_sweep_run(&c, C5_SW_MODEL, &c.base, &shipped, &err) == 0);
    c5_sweep_point pw = c5_sweep_point_with(&c.base, &wk, 3);
    CHECK(c5_sweep_run(&c, C5_SW_MODEL, &pw, &narrow, &err) == 0);
    CHECK_MSG(shipped.ok && narrow.ok && narrow.rmse > 1.05 * shipped.rmse, "%s: width.pos=3 RMSE %g, shipped %g",
              what, narrow.rmse, shipped.rmse);
    /* the caster: every k draws plain mode's image (its scheme is exact) */
    c5_sweep_point p = c.base;
    for (int k = 1; k <= 16; k *= 4) {
        p.k = k;
        c5_sweep_result r;
        CHECK(c5_sweep_run(&c, C5_SW_CAST, &p, &r, &err) == 0);
        CHECK_MSG(r.ok, "%s", r.msg);
        CHECK_INT(r.identical_to_plain, 1);
        CHECK(isnan(r.board_s) && r.rmse > 0);
    }
    c5_sweep_free(&c);
    c5_supervol_free(&sv);
}

TEST(sweep_cref_error_falls_with_step)
{
    error_falls("{'volumes': [{'generator': 'blobs', 'dims': [20, 20, 20], 'seed': 2}],"
                " 'transfer_function': {'opacity': [[0, 0], [60, 0], [140, 0.08], [255, 0.2]],"
                "   'color': [[0, 0.2, 0.3, 0.9], [128, 0.95, 0.9, 0.8], [255, 1, 0.4, 0.1]]},"
                " 'camera': {'eye': [50, -35, 40], 'target': [10, 10, 10], 'fov': 34, 'width': 24, 'height': 24}}",
                "blobs");
}

TEST(sweep_marschner_lobb_reference_is_analytic)
{
    const char *ml = "{'volumes': [{'generator': 'marschner_lobb', 'dims': [24, 24, 24], 'f_m': 6, 'alpha': 0.25}],"
                     " 'transfer_function': {'opacity': [[0, 0], [104, 0], [128, 0.3], [152, 0], [255, 0]],"
                     "   'color': [[0, 0.2, 0.3, 0.9], [128, 0.95, 0.95, 0.95], [255, 1, 0.3, 0.1]]},"
                     " 'camera': {'eye': [60, -35, 45], 'target': [12, 12, 12], 'fov': 34, 'width': 24,"
                     "   'height': 24}}";
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    CHECK(c5_scene_parse(c5t_json(ml), NULL, "ml", &s, &err) == 0);
    CHECK(c5_supervol_build(&s, &sv, &err) == 0);
    CHECK(c5_sweep_is_marschner_lobb(&s, &sv));
    c5_sweep_ctx c;
    CHECK(c5_sweep_init(&c, &s, &sv, 1, 0, &err) == 0);
    CHECK(c.analytic && c.ml_f_m == 6 && c.ml_alpha == 0.25);
    c5_sweep_free(&c);
    /* moved inside a larger grid, the volume no longer is the whole signal */
    s.grid.dims[0] = s.grid.dims[1] = s.grid.dims[2] = 30;
    c5_supervol_free(&sv);
    CHECK(c5_supervol_build(&s, &sv, &err) == 0);
    CHECK(!c5_sweep_is_marschner_lobb(&s, &sv));
    c5_supervol_free(&sv);
    error_falls(ml, "marschner-lobb");
}
