/* The error/time sweep behind `cube5 sweep` (docs/sweep.md): a scene rendered over
 * a range of one setting ("knob") at a time, each image measured against a converged
 * reference (docs/compare.md's PSNR, RMSE and largest error) and timed.
 *
 *   knob       what it changes                                     renderers
 *   step       sample step in voxels (the grid's smallest spacing)  cref, model
 *   et         early-termination opacity, (0, 1]                    cref, model
 *   bounces    reflect/refract generations, 0..15                   cref, model
 *   width.NAME a datapath signal's fraction bits (widths.h)         model
 *   k          the caster's approximation interval, 1..16 (2^n)     cast
 *
 * The reference is cref at (the finest step the sweep renders, or the scene's) / 8 with no
 * early termination (et 1) and max(15, scene's) bounces, or for a Marschner-Lobb scene the
 * same render of the analytic signal (cref's c5_field) instead of the voxels; the caster's
 * rows are measured against the caster in plain mode at its step / 8 without early
 * termination (the caster draws under the peer benchmark's conventions, not cref's). */
#ifndef C5_SWEEP_H
#define C5_SWEEP_H

#include <stdint.h>
#include <stdio.h>

#include "cast.h"
#include "cref.h"
#include "err.h"
#include "image.h"
#include "metrics.h"
#include "scene.h"
#include "supervol.h"
#include "widths.h"

#define C5_SWEEP_MAX_VALUES 32
#define C5_SWEEP_MAX_KNOBS (4 + C5_W_COUNT)
/* The board model's limit on step / spacing (step_vec SQ3.15, docs/board-model.md). */
#define C5_SWEEP_MAX_STEP 7.99
/* The model's largest max_bounces (the packet's 4-bit generation). */
#define C5_SWEEP_MAX_BOUNCES 15
/* The reference is this many times finer than the finest step the sweep renders. */
#define C5_SWEEP_REF_DIV 8

typedef enum { C5_KNOB_STEP, C5_KNOB_ET, C5_KNOB_BOUNCES, C5_KNOB_WIDTH, C5_KNOB_K } c5_knob_kind;
typedef enum { C5_SW_CREF, C5_SW_MODEL, C5_SW_CAST } c5_sweep_renderer;

typedef struct {
    char name[24];           /* "step", "et", "bounces", "width.pos", ..., "k" */
    c5_knob_kind kind;
    c5_width_id width;       /* C5_KNOB_WIDTH */
    int n;
    double v[C5_SWEEP_MAX_VALUES];
} c5_sweep_knob;

/* "NAME=V1,V2,...": a known knob, at least one value, every value a number in the knob's
 * range (step in (0, 7.99) voxels; et in (0, 1]; bounces a whole number 0..15; width.NAME a
 * whole number 1..shipped, checked by c5_widths_set; k one of 1, 2, 4, 8, 16), no value
 * twice. -1 with a message naming the knob and the value otherwise. */
int c5_sweep_knob_parse(const char *spec, c5_sweep_knob *out, c5_err *err);

/* One point of the sweep: every knob's value. */
typedef struct {
    double step; /* voxels */
    double et;
    int bounces;
    c5_widths widths;
    int k;
} c5_sweep_point;

/* The point with knob `kn` at value v (the others as in *base). */
c5_sweep_point c5_sweep_point_with(const c5_sweep_point *base, const c5_sweep_knob *kn, double v);
/* 1 when v is the knob's value in *base (the scene's setting, the shipped width, the k
 * the caster takes by default for the view). */
int c5_sweep_is_default(const c5_sweep_point *base, const c5_sweep_knob *kn, double v);
/* The renderers a knob is measured on: 1 to 2 of them into r[], returns how many. */
int c5_sweep_knob_renderers(const c5_sweep_knob *kn, c5_sweep_renderer r[2]);
const char *c5_sweep_renderer_name(c5_sweep_renderer r);

/* The sweep with no --knob: each knob over a few values around base (docs/sweep.md); k only
 * when has_volume. Returns the number of knobs written to out[C5_SWEEP_MAX_KNOBS]. */
int c5_sweep_default_knobs(const c5_sweep_point *base, int has_volume, c5_sweep_knob *out);

/* Pareto front of n points (t[i], e[i]), smaller is better in both: on[i] = 1 when no other
 * point is at least as good in both and better in one. Equal points do not dominate each
 * other (both are on the front). A point with a NaN coordinate is never on it, nor
 * dominates. */
void c5_sweep_pareto(const double *t, const double *e, int n, int *on);

/* ---- running ------------------------------------------------------------------------- */

typedef struct {
    int ok;                  /* 0: the renderer refused or failed; msg says why */
    char msg[1024];
    double psnr_db, rmse, max_abs_err;
    double host_s;           /* host wall time around the renderer's call */
    double board_s;          /* modelled board time (model rows), else NAN */
    uint64_t samples;
    int identical_to_plain;  /* cast rows: 1 when the image equals plain mode's at the same step; else -1 */
} c5_sweep_result;

typedef struct {
    const c5_scene *scene;   /* as loaded: its settings are the defaults */
    const c5_supervol *sv;
    int threads;             /* cref's threads and the caster's workers (<= 0: one per CPU) */
    double voxel;            /* world units of one voxel of step: the smallest spacing (1 without a volume) */
    c5_sweep_point base;     /* the scene's settings, shipped widths, the caster's default k */
    int has_volume;
    int analytic;            /* the scene is the Marschner-Lobb signal: the reference is its analytic truth */
    double ml_f_m, ml_alpha;
    /* the reference (filled by c5_sweep_reference) */
    double ref_step, ref_coarse_step, ref_et; /* voxels */
    int ref_bounces;
    double ref_wall_s;
    c5_image ref;
    c5_image_diff ref_conv;  /* the reference at ref_coarse_step (= 2 ref_step) against ref_step */
    /* the caster (only when a k knob is swept) */
    int cast_ready;
    c5_cast_volume *cv;
    c5_cast_camera cam;
    int cast_shading;
    c5_tf_desc cast_tf;
    c5_image cast_ref, cast_plain;
    double cast_ref_step;
    c5_image_diff cast_conv;
} c5_sweep_ctx;

/* The context of a scene (its super volume built). Builds the caster's volume when need_cast
 * (a scene without a volume cannot be cast: -1 with a message). */
int c5_sweep_init(c5_sweep_ctx *c, const c5_scene *s, const c5_supervol *sv, int threads, int need_cast,
                  c5_err *err);
/* Renders the references: cref (or the analytic truth) at finest / C5_SWEEP_REF_DIV and at
 * twice that (the convergence check), and when the caster is ready its plain reference the
 * same way and its plain image at base.step. `finest`: the smallest step in voxels the
 * sweep renders. After each of its c5_sweep_reference_steps() renders, `progress` (when not
 * NULL) gets what was rendered and its host seconds. */
typedef void (*c5_sweep_progress_fn)(void *arg, const char *what, double s);
int c5_sweep_reference_steps(const c5_sweep_ctx *c);
int c5_sweep_reference(c5_sweep_ctx *c, double finest, c5_sweep_progress_fn progress, void *arg, c5_err *err);
/* One run: renders the point with r and measures it against the reference. Returns -1 only
 * for an error of the sweep itself (out of memory); a renderer that refuses the point gives
 * out->ok = 0 and 0. */
int c5_sweep_run(c5_sweep_ctx *c, c5_sweep_renderer r, const c5_sweep_point *p, c5_sweep_result *out, c5_err *err);
void c5_sweep_free(c5_sweep_ctx *c);

/* 1 when the scene's only volume is the Marschner-Lobb generator filling the whole grid
 * (offset 0, grid dims its own): then its analytic signal is known everywhere. */
int c5_sweep_is_marschner_lobb(const c5_scene *s, const c5_supervol *sv);

#endif
