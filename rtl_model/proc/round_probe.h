/* The rounding and saturation probe: which event each rounder and saturator of the datapath
 * met, per named site, for the functional coverage of the vectors (spec/coverage.toml
 * [[site]], scripts/vectors_coverage.py). Compiled in only with -DC5_ROUND_PROBE, which only
 * the live-reference library has (Makefile, REF_SO): there the coverage replays each vector
 * through the model's own block functions. Everywhere else every macro is empty, so the
 * sample loop is the same code with or without this header. */
#ifndef C5_ROUND_PROBE_H
#define C5_ROUND_PROBE_H

/* The sites: one per rounding (or clamp) the blocks' formats declare, in the order the
 * blocks run them. C5_RS_NONE collects a rounding no site claimed: the coverage refuses a
 * vector that has one, so a new rounder cannot go uncounted. */
#define C5_ROUND_SITES(X)                                                                     \
    X(NONE, "none")                                                                           \
    X(INTERP_VALUE, "interp.value")                                                           \
    X(GRAD_BLEND, "gradient.blend")                                                           \
    X(GRAD_SCALE, "gradient.scale")                                                           \
    X(CLASSIFY_LERP, "classify.lerp")                                                         \
    X(SHADE_NORMAL, "shade.normal")                                                           \
    X(SHADE_FACING, "shade.facing")                                                           \
    X(SHADE_LIGHT_DIR, "shade.light_dir")                                                     \
    X(SHADE_NDL, "shade.ndl")                                                                 \
    X(SHADE_HALF, "shade.half")                                                               \
    X(SHADE_NDH, "shade.ndh")                                                                 \
    X(SHADE_POW, "shade.pow")                                                                 \
    X(SHADE_K, "shade.k")                                                                     \
    X(SHADE_KS, "shade.ks")                                                                   \
    X(SHADE_CHANNEL, "shade.channel")                                                         \
    X(COMPOSITE_RGB, "composite.rgb")                                                         \
    X(COMPOSITE_OPA, "composite.opa")

#define C5_RS_ENUM(id, name) C5_RS_##id,
enum { C5_ROUND_SITES(C5_RS_ENUM) C5_RS_COUNT };
#undef C5_RS_ENUM

/* Events, a bit each: the dropped bits were zero; below half (rounded down, towards minus
 * infinity); above half (up); exactly half with an even quotient (kept) or an odd one
 * (up, to even); a clamp to the lower or the upper bound. */
enum {
    C5_EV_EXACT = 1,
    C5_EV_DOWN = 2,
    C5_EV_UP = 4,
    C5_EV_TIE_KEPT = 8,
    C5_EV_TIE_UP = 16,
    C5_EV_SAT_LO = 32,
    C5_EV_SAT_HI = 64,
};

#ifdef C5_ROUND_PROBE
extern int c5_round_site;                     /* the site of the next rounding or clamp */
extern unsigned c5_round_seen[C5_RS_COUNT];   /* per site, the events since the last reset */
/* cmp: the dropped part against half (<0, 0, >0); zero: nothing dropped; odd: the quotient
 * before rounding was odd. */
#define C5_ROUND_AT(site) (c5_round_site = (site))
#define C5_ROUND_NOTE(zero, cmp, odd)                                                         \
    (c5_round_seen[c5_round_site] |= (zero) ? C5_EV_EXACT : (cmp) < 0 ? C5_EV_DOWN            \
                                                 : (cmp) > 0 ? C5_EV_UP                       \
                                                 : (odd) ? C5_EV_TIE_UP : C5_EV_TIE_KEPT)
#define C5_SAT_NOTE(ev) (c5_round_seen[c5_round_site] |= (ev))
#else
#define C5_ROUND_AT(site) ((void)0)
#define C5_ROUND_NOTE(zero, cmp, odd) ((void)0)
#define C5_SAT_NOTE(ev) ((void)0)
#endif

#endif
