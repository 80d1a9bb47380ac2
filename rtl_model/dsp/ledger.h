/* The DSP's ledger of a camera path (docs/cell-tree.md, "The certificate"): how many loads a
 * frame that follows a schedule may make beyond Max Work's. The board holds the frame to it
 * with Max Work's shadow (mw_shadow.h), so a frame never loses more than its budget, and the
 * path's bank (stale_plan.h: the exact saving so far) never falls below minus one allowance. */
#ifndef C5_LEDGER_H
#define C5_LEDGER_H

#include <stdint.h>

#include "scene.h"
#include "stale_plan.h"

/* The allowance a frame may risk beyond the bank: max(this % of the previous frame's Max Work
 * loads, one load). Fitted on one generated family of camera paths and shown on another
 * (docs/cell-tree.md, "The family"). */
#define C5_LEDGER_ALLOWANCE_PCT 25.0

/* A frame with no replayed evidence of the path's speed (its previous frame followed no
 * schedule) risks its allowance only when the rays its set-up queued overlap the previous
 * frame's this much (c5_board_stats.start_overlap). Fitted with the allowance. */
#define C5_LEDGER_START_OVERLAP 0.8

/* The allowance of a frame following a schedule made with replay p (NULL: none). */
int64_t c5_ledger_allowance(const c5_stale_plan *p);

/* The frame's budget: p's bank, plus one allowance unless p's replay shows that the schedule
 * followed in p's frame would have saved less than an allowance there, or, without that
 * replay, the start queues overlap the previous frame's less than C5_LEDGER_START_OVERLAP
 * (start_overlap < 0: not compared, no evidence either way). A frame whose camera
 * registers are p's (frame_key) builds p's tree, so p's replay is the frame: *identical = 1,
 * and the budget follows the schedule to its end when it replays no longer than Max Work,
 * else none (0). */
int64_t c5_ledger_budget(const c5_stale_plan *p, uint64_t frame_key, double start_overlap, int *identical);

/* The camera registers the eye-ray set-up reads (eye, target, up, field of view, image size),
 * hashed: two frames with one key trace the same rays through the same super volume. */
uint64_t c5_frame_key(const c5_camera *c, int w, int h);

#endif
