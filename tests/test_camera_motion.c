/* Generated camera motion (common/camera_motion.h): orbits keep the eye's distance and
 * height and turn by the asked angle, jumps come where and as often as asked, from the
 * seed alone, bad values are refused. */
#include <math.h>
#include <string.h>

#include "camera.h"
#include "camera_motion.h"
#include "harness.h"
#include "vec.h"

#define PI 3.14159265358979323846

static c5_camera base_cam(void)
{
    c5_camera c = {.eye = {260, -330, 120}, .target = {-20, 20, 0}, .up = {0, 0, 1}, .fov_deg = 36};
    return c;
}

/* The eye's angle about the target in the plane normal to up (up = z here). */
static double azimuth(const c5_camera *c)
{
    return atan2(c->eye.y - c->target.y, c->eye.x - c->target.x);
}

TEST(motion_still_is_base)
{
    c5_camera b = base_cam(), c;
    c5_motion m = {0};
    CHECK(!c5_motion_active(&m));
    for (int f = -2; f < 20; f++) {
        c = c5_motion_camera(&b, &m, f);
        CHECK(!memcmp(&c, &b, sizeof c));
    }
    m.dolly = 1;
    CHECK(!c5_motion_active(&m));
}

TEST(motion_orbit_turns_by_deg)
{
    c5_camera b = base_cam();
    double r0 = v3_len(v3_sub(b.eye, b.target));
    double degs[] = {2, 8, 30, 90, -45, 360, 1000};
    for (size_t k = 0; k < sizeof degs / sizeof *degs; k++) {
        c5_motion m = {.orbit_deg = degs[k]};
        CHECK(c5_motion_active(&m));
        CHECK(c5_motion_check(&m, NULL) == 0);
        for (int f = 0; f < 16; f++) {
            c5_camera c = c5_motion_camera(&b, &m, f);
            CHECK_NEAR(v3_len(v3_sub(c.eye, c.target)), r0, 1e-9 * r0);
            CHECK_NEAR(c.eye.z, b.eye.z, 1e-9 * r0); /* height along up kept */
            CHECK(!memcmp(&c.target, &b.target, sizeof c.target) && !memcmp(&c.up, &b.up, sizeof c.up));
            double want = azimuth(&b) + degs[k] * f * PI / 180, got = azimuth(&c);
            CHECK_NEAR(cos(got - want), 1.0, 1e-9);
            CHECK(c5_camera_problem(&c) == NULL);
        }
    }
    /* Four quarter turns are home again. */
    c5_motion q = {.orbit_deg = 90};
    c5_camera c = c5_motion_camera(&b, &q, 4);
    CHECK_NEAR(c.eye.x, b.eye.x, 1e-9 * r0);
    CHECK_NEAR(c.eye.y, b.eye.y, 1e-9 * r0);
}

TEST(motion_jumps_every_k)
{
    c5_camera b = base_cam();
    double r0 = v3_len(v3_sub(b.eye, b.target));
    c5_motion m = {0};
    CHECK(c5_motion_parse_jumps("--jumps", "7:3", &m, NULL) == 0);
    CHECK_INT(m.jump_every, 3);
    CHECK(c5_motion_active(&m));
    c5_camera prev = c5_motion_camera(&b, &m, 0);
    CHECK(!memcmp(&prev, &b, sizeof b));
    int moved = 0;
    for (int f = 1; f < 60; f++) {
        CHECK_INT(c5_motion_jumps_at(&m, f), f % 3 == 0);
        c5_camera c = c5_motion_camera(&b, &m, f);
        int same = !memcmp(&c.eye, &prev.eye, sizeof c.eye);
        CHECK_MSG(same == !(f % 3 == 0), "frame %d: a jump iff f %% 3 == 0 (no orbit)", f);
        moved += !same;
        CHECK_NEAR(v3_len(v3_sub(c.eye, c.target)), r0, 1e-9 * r0);
        double el = asin((c.eye.z - c.target.z) / r0) * 180 / PI;
        CHECK_MSG(fabs(el) <= 60 + 1e-9, "frame %d: elevation %g", f, el);
        CHECK(c5_camera_problem(&c) == NULL);
        prev = c;
    }
    CHECK_INT(moved, 19);
    /* The same seed gives the same cameras, another seed others. */
    c5_motion m2 = m, m3 = m;
    m3.jump_seed = 8;
    c5_camera a = c5_motion_camera(&b, &m, 9), a2 = c5_motion_camera(&b, &m2, 9), a3 = c5_motion_camera(&b, &m3, 9);
    CHECK(!memcmp(&a, &a2, sizeof a));
    CHECK(memcmp(&a.eye, &a3.eye, sizeof a.eye) != 0);
    CHECK(!c5_motion_jumps_at(&m, 0));
}

TEST(motion_jumps_with_orbit_continue_from_the_jump)
{
    c5_camera b = base_cam();
    c5_motion j = {.jumps = 1, .jump_seed = 3, .jump_every = 5}, jo = j;
    jo.orbit_deg = 10;
    c5_camera at = c5_motion_camera(&b, &j, 5), at_o = c5_motion_camera(&b, &jo, 5), later = c5_motion_camera(&b, &jo, 7);
    CHECK(!memcmp(&at, &at_o, sizeof at)); /* the jump frame itself: no turn yet */
    CHECK_NEAR(cos(azimuth(&later) - azimuth(&at) - 20 * PI / 180), 1.0, 1e-9);
}

TEST(motion_jumps_by_probability)
{
    c5_motion m = {0};
    CHECK(c5_motion_parse_jumps("--jumps", "11:p0.25", &m, NULL) == 0);
    CHECK_INT(m.jump_every, 0);
    int n = 0, frames = 20000;
    for (int f = 1; f <= frames; f++)
        n += c5_motion_jumps_at(&m, f);
    CHECK_MSG(fabs((double)n / frames - 0.25) < 0.02, "%d jumps in %d frames at p = 0.25", n, frames);
    CHECK(c5_motion_parse_jumps("--jumps", "11:p1", &m, NULL) == 0);
    for (int f = 1; f < 50; f++)
        CHECK(c5_motion_jumps_at(&m, f));
}

TEST(motion_dolly_scales_distance)
{
    c5_camera b = base_cam();
    double r0 = v3_len(v3_sub(b.eye, b.target));
    c5_motion m = {0};
    CHECK(c5_motion_parse_dolly("--dolly", "0.9", &m, NULL) == 0);
    CHECK(c5_motion_active(&m));
    for (int f = 0; f < 10; f++) {
        c5_camera c = c5_motion_camera(&b, &m, f);
        CHECK_NEAR(v3_len(v3_sub(c.eye, c.target)), r0 * pow(0.9, f), 1e-9 * r0);
    }
}

TEST(motion_bad_values_refused)
{
    c5_motion m = {0};
    c5_err e;
    const char *orbits[] = {"nan", "inf", "-inf", "abc", "", "1e400", "3601", "2deg"};
    for (size_t k = 0; k < sizeof orbits / sizeof *orbits; k++) {
        CHECK_MSG(c5_motion_parse_orbit("--orbit", orbits[k], &m, &e) != 0, "--orbit '%s' accepted", orbits[k]);
        CHECK(strstr(e.msg, "--orbit") != NULL);
    }
    const char *jumps[] = {"", "-1", "x", "1:", "1:0", "1:-2", "1:p0", "1:p1.5", "1:pnan", "1:q", ":4",
                           "99999999999999999999999"};
    for (size_t k = 0; k < sizeof jumps / sizeof *jumps; k++) {
        CHECK_MSG(c5_motion_parse_jumps("--jumps", jumps[k], &m, &e) != 0, "--jumps '%s' accepted", jumps[k]);
        CHECK(strstr(e.msg, "--jumps") != NULL);
    }
    const char *dollies[] = {"0", "0.1", "3", "nan", "-1"};
    for (size_t k = 0; k < sizeof dollies / sizeof *dollies; k++)
        CHECK_MSG(c5_motion_parse_dolly("--dolly", dollies[k], &m, &e) != 0, "--dolly '%s' accepted", dollies[k]);
    c5_motion bad = {.orbit_deg = NAN};
    CHECK(c5_motion_check(&bad, &e) != 0);
    bad = (c5_motion){.jumps = 1, .jump_every = 0, .jump_prob = 0};
    CHECK(c5_motion_check(&bad, &e) != 0);
    bad = (c5_motion){.dolly = 5};
    CHECK(c5_motion_check(&bad, &e) != 0);
    c5_motion good = {.orbit_deg = -30, .jumps = 1, .jump_every = 2, .dolly = 0.95};
    CHECK(c5_motion_check(&good, &e) == 0);
}
