/* Generated camera motion: the camera of every frame of an animation made from one base
 * camera, for studies of how a schedule made from the previous frame's Cell Tree fares when
 * the view changes (docs/cell-tree.md, "Camera motion"). Three motions, combined:
 *
 * - orbit: the eye turns about the target around the camera's up axis, D degrees a frame
 *   (0: still; negative: the other way);
 * - jumps (cuts): from a seeded stream, a new eye on the sphere about the target through
 *   the base eye (elevation within +-60 degrees of the plane normal to up), every K frames or
 *   at each frame with probability p; the orbit continues from the new eye;
 * - dolly: the eye's distance to the target times F a frame (F < 1 moves in: the eye
 *   passes surfaces, so what occludes what changes).
 *
 * Frame f's camera is a pure function of (base, motion, f): the same bits on every machine
 * and in any order of calls. */
#ifndef C5_CAMERA_MOTION_H
#define C5_CAMERA_MOTION_H

#include <stdint.h>

#include "err.h"
#include "scene.h"

#define C5_MOTION_MAX_DEG 3600.0  /* |orbit| per frame; any angle, 10 turns keep it meaningful */
#define C5_MOTION_MIN_DOLLY 0.5   /* dolly factor per frame, [0.5, 2] */
#define C5_MOTION_MAX_DOLLY 2.0
#define C5_MOTION_MAX_EVERY 1000000

typedef struct {
    double orbit_deg;   /* degrees a frame about the target around up; 0: none */
    int jumps;          /* 1: random jumps */
    uint64_t jump_seed; /* the jumps' stream */
    int jump_every;     /* a jump every K frames (frames K, 2K, ...); 0: by jump_prob */
    double jump_prob;   /* with jump_every 0: each frame >= 1 jumps with this probability */
    double dolly;       /* eye distance factor a frame; 0 or 1: none */
} c5_motion;

/* 1 when the motion moves the camera at all. */
int c5_motion_active(const c5_motion *m);
/* 0, or -1 with a message naming the bad value (NaN, out of range). */
int c5_motion_check(const c5_motion *m, c5_err *err);
/* Parsers of the CLI's spellings, each 0 or -1 with a message naming `opt`:
 * orbit "DEG"; jumps "SEED", "SEED:EVERY" (default every 4 frames) or "SEED:pPROB";
 * dolly "F". */
int c5_motion_parse_orbit(const char *opt, const char *v, c5_motion *m, c5_err *err);
int c5_motion_parse_jumps(const char *opt, const char *v, c5_motion *m, c5_err *err);
int c5_motion_parse_dolly(const char *opt, const char *v, c5_motion *m, c5_err *err);
/* 1 when frame f starts a new view (a jump); frame 0 never does. */
int c5_motion_jumps_at(const c5_motion *m, int frame);
/* The camera of frame `frame` (< 0 reads as 0): base moved by m. The target, up and fov
 * are base's. */
c5_camera c5_motion_camera(const c5_camera *base, const c5_motion *m, int frame);

#endif
