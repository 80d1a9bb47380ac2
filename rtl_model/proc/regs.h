/* The frame registers: everything the DSP loads into the ray processor before a frame,
 * converted once from the scene's doubles into the datapath formats (docs/bit-layouts.md,
 * "signals"). The conversion is the only floating point of the model besides eye-ray
 * directions (docs/board-model.md, "where floating point remains"). */
#ifndef C5_REGS_H
#define C5_REGS_H

#include <stdint.h>

#include "board.h"
#include "ray.h"

#define C5_POW_BITS 10 /* specular power table: 2^10 + 1 entries over N.H in [0, 1] */

typedef struct {
    int kind;          /* C5_LIGHT_POINT / C5_LIGHT_DIRECTIONAL */
    int64_t pos[3];    /* point: geom_coord SQ13.15 */
    int64_t dir[3];    /* directional: unit vector towards the light, SQ1.14 */
    int64_t intensity; /* light_term UQ4.12 */
    int shadows;
} c5_light_regs;

typedef struct {
    int kind;              /* c5_surface_kind */
    int64_t p[3];          /* plane point / rect corner / sphere centre: SQ13.15 */
    int64_t n[3];          /* plane, rect: unit normal SQ1.14 */
    int64_t eu[3], ev[3];  /* rect edges SQ13.15 */
    int64_t r;             /* sphere radius SQ13.15 */
    int64_t color[3];      /* UQ1.15 */
    int64_t ambient, diffuse; /* light_term UQ4.12 */
    int64_t refl, transp, kdiff; /* UQ1.15: rho, tau, 1 - rho - tau */
    int64_t eta_in, eta_out;     /* 1/ior and ior, UQ4.28 (refraction unit) */
} c5_surface_regs;

typedef struct {
    /* grid and cells */
    int dims[3];
    int64_t gscale[3];   /* s_a / s_min, UQ8.16: voxel -> geom coordinates */
    int64_t vscale[3];   /* s_min / s_a, UQ1.20: geom -> voxel coordinates */
    int64_t gdims[3];    /* grid box in geom coordinates, SQ13.15 */
    int64_t step_k[3];   /* step / s_a, UQ4.20: step vector = dir * step_k */
    int64_t step_g;      /* step / s_min, UQ4.20: the step in geom coordinates */
    int64_t eps_g;       /* spawned rays ignore hits closer than this to their origin (eye rays: 0), SQ13.15 raw */
    int has_volume;
    /* classification and shading */
    int32_t tf[256][4];  /* tf_rgba UQ1.15, alpha step-corrected */
    int64_t gs[3];       /* s_min / s_a, UQ1.15: gradient scale */
    int64_t ka, kd, ks;  /* light_term UQ4.12 */
    int32_t pow_tab[(1 << C5_POW_BITS) + 1]; /* (N.H)^p, UQ1.15 */
    int64_t a_max;       /* max_opacity, UQ1.15 */
    int n_lights;
    c5_light_regs lights[C5_MAX_LIGHTS];
    int n_surfaces;
    c5_surface_regs surf[C5_MAX_SURFACES];
    /* spawning and accumulation */
    int64_t min_w;       /* min_weight, UQ1.15 (rounded up: a weight below it is cut) */
    int64_t min_rgb;     /* min_weight, UQ2.12 (shadow rays' radiance) */
    int max_bounces;
    int64_t bg[3];       /* background UQ2.12 */
    /* datapath widths (widths.h): per signal the fraction bits dropped where the datapath
     * produces it, shipped - width; all 0 (a zeroed struct too) is the shipped board */
    int nsh[C5_W_COUNT];
    c5_board_stages st;
} c5_frame_regs;

/* Fills the registers from the scene, or refuses a scene the model's formats cannot hold
 * (each limit named in the message, docs/board-model.md "limits"). */
int c5_regs_build(const c5_scene *s, const c5_supervol *sv, const c5_board_opts *o, c5_frame_regs *r,
                  c5_err *err);

/* The stages the scene needs (the summary's "what ran"). */
c5_board_stages c5_regs_stages(const c5_scene *s, const c5_supervol *sv, int cells);

/* Double -> raw fixed point with frac_bits 0..62, half to even, saturated (counted nowhere:
 * set-up values are range-checked before conversion). */
int64_t c5_regs_fx(double x, int frac_bits, int64_t lo, int64_t hi);

/* A world point in geom coordinates (world / min spacing from the grid origin, SQ13.15);
 * -1 with a message naming `what` when it lies beyond the format. */
int c5_regs_geom_point(c5_vec3 p, const c5_supervol *sv, int64_t out[3], const char *what, c5_err *err);
/* A direction normalised and rounded to SQ1.14. */
void c5_regs_unit14(c5_vec3 d, int64_t out[3]);

#endif
