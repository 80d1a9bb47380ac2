/* Eye rays (docs/rendering-spec.md sec. 2): one ray through each pixel centre, py = 0 the top
 * row. Shared by cref and the board model's DSP so that both start from the same rays. */
#ifndef C5_CAMERA_H
#define C5_CAMERA_H

#include "scene.h"

typedef struct {
    c5_vec3 eye, f, right, up;
    double tan_half, aspect;
    int w, h;
} c5_camera_basis;

/* Why the camera cannot frame a view (the eye on the target, up zero or parallel to the
 * view direction), or NULL when it can. The scene parser asks it of every frame of a
 * camera path, so a render never meets a camera that c5_camera_basis_make refuses. */
const char *c5_camera_problem(const c5_camera *cam);
/* 0, or -1 with a message when up is parallel to the view (a path can blend two keys'
 * up vectors into one) or the eye is on the target. */
int c5_camera_basis_make(const c5_camera *cam, int w, int h, int frame, c5_camera_basis *b, c5_err *err);
/* Unit direction of the ray through pixel (px, py). */
c5_vec3 c5_camera_pixel_dir(const c5_camera_basis *b, int px, int py);

#endif
