/* --orbit, --jumps, --dolly (motion_cli.h). */
#include <stddef.h>

#include "motion_cli.h"

static int orbit_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    return c5_motion_parse_orbit(o->name, v, field, err);
}

static int jumps_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    return c5_motion_parse_jumps(o->name, v, field, err);
}

static int dolly_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    return c5_motion_parse_dolly(o->name, v, field, err);
}

#define GIVEN C5_SEEN(c5_motion_args, given)
const c5_opt c5_motion_opts[] = {
    {"--orbit", "DEG", orbit_opt, offsetof(c5_motion_args, m), 0, 0, GIVEN,
     "camera motion: the eye turns DEG degrees a frame about the target around the camera's up axis (0: still), "
     "from the path's first camera"},
    {"--jumps", "SEED[:EVERY|:pPROB]", jumps_opt, offsetof(c5_motion_args, m), 0, 0, GIVEN,
     "camera motion: cuts to a random view (an eye on the sphere about the target), every EVERY frames (default 4) "
     "or with probability PROB a frame"},
    {"--dolly", "F", dolly_opt, offsetof(c5_motion_args, m), 0, 0, GIVEN,
     "camera motion: the eye's distance to the target times F a frame (0.5..2; below 1 the eye moves in past "
     "surfaces). With any motion, --frames defaults to 8"},
    {0},
};
#undef GIVEN

int c5_motion_check_frames(const c5_motion_args *ma, c5_scene *s, int frames, const char *label, c5_err *err)
{
    s->camera = c5_scene_camera_at(s, 0);
    for (int f = 0; f < frames; f++) {
        c5_camera cam = c5_motion_camera(&s->camera, &ma->m, f);
        const char *problem = c5_camera_problem(&cam);
        if (problem)
            return c5_fail(err, "%s: camera motion: frame %d: %s", label, f, problem);
    }
    return 0;
}
