/* Generated camera motion (camera_motion.h). */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "camera_motion.h"
#include "rng.h"
#include "vec.h"

#define PI 3.14159265358979323846
#define JUMP_MAX_ELEV_DEG 60.0 /* keeps a jumped view away from up (a camera needs up off the view) */
#define JUMP_EVERY_DEFAULT 4

int c5_motion_active(const c5_motion *m)
{
    return m->orbit_deg != 0 || m->jumps || (m->dolly != 0 && m->dolly != 1);
}

int c5_motion_check(const c5_motion *m, c5_err *err)
{
    if (!isfinite(m->orbit_deg) || fabs(m->orbit_deg) > C5_MOTION_MAX_DEG)
        return c5_fail(err, "orbit: %g degrees a frame is not a number in [-%g, %g]", m->orbit_deg,
                       C5_MOTION_MAX_DEG, C5_MOTION_MAX_DEG);
    if (m->jumps && (m->jump_every < 0 || m->jump_every > C5_MOTION_MAX_EVERY))
        return c5_fail(err, "jumps: every %d frames is not in 1..%d", m->jump_every, C5_MOTION_MAX_EVERY);
    if (m->jumps && m->jump_every == 0 && !(m->jump_prob > 0 && m->jump_prob <= 1))
        return c5_fail(err, "jumps: probability %g is not in (0, 1]", m->jump_prob);
    if (m->dolly != 0 && !(m->dolly >= C5_MOTION_MIN_DOLLY && m->dolly <= C5_MOTION_MAX_DOLLY))
        return c5_fail(err, "dolly: factor %g a frame is not in [%g, %g]", m->dolly, C5_MOTION_MIN_DOLLY,
                       C5_MOTION_MAX_DOLLY);
    return 0;
}

/* A finite number filling all of s, or -1 with a message. */
static int parse_num(const char *opt, const char *s, double *out, c5_err *err)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (!*s || *end || errno == ERANGE || !isfinite(v))
        return c5_fail(err, "%s: expected a finite number, got '%s'", opt, s);
    *out = v;
    return 0;
}

int c5_motion_parse_orbit(const char *opt, const char *v, c5_motion *m, c5_err *err)
{
    double d;
    if (parse_num(opt, v, &d, err) != 0)
        return -1;
    if (fabs(d) > C5_MOTION_MAX_DEG)
        return c5_fail(err, "%s: %s degrees a frame is outside [-%g, %g]", opt, v, C5_MOTION_MAX_DEG,
                       C5_MOTION_MAX_DEG);
    m->orbit_deg = d;
    return 0;
}

int c5_motion_parse_dolly(const char *opt, const char *v, c5_motion *m, c5_err *err)
{
    double d;
    if (parse_num(opt, v, &d, err) != 0)
        return -1;
    if (!(d >= C5_MOTION_MIN_DOLLY && d <= C5_MOTION_MAX_DOLLY))
        return c5_fail(err, "%s: factor %s a frame is outside [%g, %g]", opt, v, C5_MOTION_MIN_DOLLY,
                       C5_MOTION_MAX_DOLLY);
    m->dolly = d;
    return 0;
}

int c5_motion_parse_jumps(const char *opt, const char *v, c5_motion *m, c5_err *err)
{
    const char *colon = strchr(v, ':');
    char seed[32];
    size_t n = colon ? (size_t)(colon - v) : strlen(v);
    if (n == 0 || n >= sizeof seed || strspn(v, "0123456789") != n)
        return c5_fail(err, "%s: expected SEED[:EVERY|:pPROB] with SEED a non-negative integer, got '%s'", opt, v);
    memcpy(seed, v, n);
    seed[n] = 0;
    errno = 0;
    unsigned long long s = strtoull(seed, NULL, 10);
    if (errno == ERANGE)
        return c5_fail(err, "%s: seed '%s' does not fit 64 bits", opt, seed);
    m->jumps = 1;
    m->jump_seed = (uint64_t)s;
    m->jump_every = JUMP_EVERY_DEFAULT;
    m->jump_prob = 0;
    if (!colon)
        return 0;
    const char *t = colon + 1;
    if (*t == 'p') {
        double p;
        if (parse_num(opt, t + 1, &p, err) != 0)
            return -1;
        if (!(p > 0 && p <= 1))
            return c5_fail(err, "%s: probability %s is outside (0, 1]", opt, t + 1);
        m->jump_every = 0;
        m->jump_prob = p;
        return 0;
    }
    char *end;
    errno = 0;
    long k = strtol(t, &end, 10);
    if (!*t || *end || errno == ERANGE || k < 1 || k > C5_MOTION_MAX_EVERY)
        return c5_fail(err, "%s: EVERY must be an integer in 1..%d (or pPROB), got '%s'", opt,
                       C5_MOTION_MAX_EVERY, t);
    m->jump_every = (int)k;
    return 0;
}

/* The stream of jump j (frame j), independent of every other frame's. */
static uint64_t jump_state(const c5_motion *m, int frame)
{
    uint64_t s = m->jump_seed ^ (0xD1B54A32D192ED03ull * (uint64_t)(frame + 1));
    c5_splitmix64(&s);
    return s;
}

int c5_motion_jumps_at(const c5_motion *m, int frame)
{
    if (!m->jumps || frame < 1)
        return 0;
    if (m->jump_every > 0)
        return frame % m->jump_every == 0;
    uint64_t s = jump_state(m, frame);
    return c5_uniform(&s) < m->jump_prob;
}

/* Rotates v about the unit axis k by a radians (Rodrigues). */
static c5_vec3 rotate(c5_vec3 v, c5_vec3 k, double a)
{
    double c = cos(a), s = sin(a);
    return v3_add(v3_add(v3_scale(v, c), v3_scale(v3_cross(k, v), s)), v3_scale(k, v3_dot(k, v) * (1 - c)));
}

c5_camera c5_motion_camera(const c5_camera *base, const c5_motion *m, int frame)
{
    c5_camera c = *base;
    if (frame < 0)
        frame = 0;
    c5_vec3 up = v3_norm(base->up), off = v3_sub(base->eye, base->target);
    double r = v3_len(off);
    int start = 0; /* the frame of the last jump */
    for (int f = frame; f >= 1 && m->jumps; f--)
        if (c5_motion_jumps_at(m, f)) {
            start = f;
            break;
        }
    if (start > 0) {
        /* A basis of the plane normal to up, then a direction at a random azimuth and
         * elevation. */
        c5_vec3 a = fabs(up.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
        c5_vec3 e1 = v3_norm(v3_cross(up, a)), e2 = v3_cross(up, e1);
        uint64_t s = jump_state(m, start);
        double az = 2 * PI * c5_uniform(&s);
        double el = (2 * c5_uniform(&s) - 1) * JUMP_MAX_ELEV_DEG * PI / 180;
        c5_vec3 d = v3_add(v3_scale(v3_add(v3_scale(e1, cos(az)), v3_scale(e2, sin(az))), cos(el)), v3_scale(up, sin(el)));
        off = v3_scale(d, r);
    }
    off = rotate(off, up, m->orbit_deg * (frame - start) * PI / 180);
    if (m->dolly != 0 && m->dolly != 1)
        off = v3_scale(off, pow(m->dolly, frame));
    c.eye = v3_add(base->target, off);
    return c;
}
