/* The camera-motion options shared by render and schedule (--orbit, --jumps, --dolly;
 * common/camera_motion.h): a camera path made from the scene's first camera. */
#ifndef C5_MOTION_CLI_H
#define C5_MOTION_CLI_H

#include "camera.h"
#include "camera_motion.h"
#include "opt_table.h"
#include "scene.h"

typedef struct {
    c5_motion m;
    int given; /* one of them given (--orbit 0 too: the path's first camera, still) */
} c5_motion_args;

extern const c5_opt c5_motion_opts[];

/* Checks every frame's camera of the motion from the scene's first camera (s->camera is set
 * to it). 0, or -1 with a message naming the frame. */
int c5_motion_check_frames(const c5_motion_args *ma, c5_scene *s, int frames, const char *label, c5_err *err);

#endif
