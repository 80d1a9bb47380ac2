/* Eye-ray directions (camera.h). */
#include "camera.h"

const char *c5_camera_problem(const c5_camera *cam)
{
    c5_vec3 f = v3_sub(cam->target, cam->eye);
    if (!(v3_len(f) > 0))
        return "the eye is on the target";
    if (!(v3_len(v3_cross(f, cam->up)) > 1e-9 * v3_len(f) * v3_len(cam->up)))
        return "up is zero or parallel to the view direction (target - eye)";
    return NULL;
}

int c5_camera_basis_make(const c5_camera *cam, int w, int h, int frame, c5_camera_basis *b, c5_err *err)
{
    c5_vec3 f = v3_sub(cam->target, cam->eye);
    const char *problem = c5_camera_problem(cam);
    if (problem)
        return c5_fail(err, "frame %d: camera: %s", frame, problem);
    b->eye = cam->eye;
    b->f = v3_norm(f);
    b->right = v3_norm(v3_cross(b->f, cam->up));
    b->up = v3_cross(b->right, b->f);
    b->tan_half = tan(cam->fov_deg * M_PI / 360);
    b->aspect = (double)w / h;
    b->w = w;
    b->h = h;
    return 0;
}

c5_vec3 c5_camera_pixel_dir(const c5_camera_basis *b, int px, int py)
{
    double sx = (2 * (px + 0.5) / b->w - 1) * b->tan_half * b->aspect;
    double sy = (1 - 2 * (py + 0.5) / b->h) * b->tan_half;
    return v3_norm(v3_add(b->f, v3_add(v3_scale(b->right, sx), v3_scale(b->up, sy))));
}
