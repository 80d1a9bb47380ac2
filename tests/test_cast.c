/* The streaming-model caster (cref/cast): every skipping mode draws the bits of marching every
 * sample, for any k, worker count, queue depth and prefetch setting, shaded and not; the
 * paper's Figure 7 case; the octree and the classification table it relies on. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "cast_internal.h"
#include "cast_sample.h"
#include "harness.h"
#include "rng.h"

static void look_at(c5_cast_camera *c, const double eye[3], const double focal[3], double fov_deg)
{
    double up0[3] = {0, 0, 1}, len = 0;
    for (int a = 0; a < 3; a++) {
        c->eye[a] = eye[a], c->focal[a] = focal[a];
        c->f[a] = focal[a] - eye[a];
        len += c->f[a] * c->f[a];
    }
    for (int a = 0; a < 3; a++)
        c->f[a] /= sqrt(len);
    if (fabs(c->f[2]) > 0.99)
        up0[1] = 1, up0[2] = 0;
    double r[3] = {c->f[1] * up0[2] - c->f[2] * up0[1], c->f[2] * up0[0] - c->f[0] * up0[2],
                   c->f[0] * up0[1] - c->f[1] * up0[0]};
    len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int a = 0; a < 3; a++)
        c->right[a] = r[a] / len;
    c->up[0] = c->right[1] * c->f[2] - c->right[2] * c->f[1];
    c->up[1] = c->right[2] * c->f[0] - c->right[0] * c->f[2];
    c->up[2] = c->right[0] * c->f[1] - c->right[1] * c->f[0];
    c->tan_half = tan(fov_deg * M_PI / 360);
}

/* Blobs of several densities in a noisy, mostly transparent field: empty bricks, partly
 * empty ones and opaque ones, so every mode has something to skip and something to keep. */
static uint8_t *blobs(const size_t d[3], uint64_t seed)
{
    uint8_t *v = malloc(d[0] * d[1] * d[2]);
    double cen[4][4];
    for (int b = 0; b < 4; b++) {
        for (int a = 0; a < 3; a++)
            cen[b][a] = c5_uniform(&seed) * (double)(d[a] - 1);
        cen[b][3] = 2 + c5_uniform(&seed) * (double)d[0] / 5;
    }
    for (size_t k = 0; k < d[2]; k++)
        for (size_t j = 0; j < d[1]; j++)
            for (size_t i = 0; i < d[0]; i++) {
                double val = 20 * c5_uniform(&seed); /* below the TF's first non-zero scalar */
                for (int b = 0; b < 4; b++) {
                    double r = hypot(hypot(i - cen[b][0], j - cen[b][1]), k - cen[b][2]);
                    if (r < cen[b][3])
                        val = fmax(val, 60 + 190 * (1 - r / cen[b][3]) * (b + 1) / 4);
                }
                v[(k * d[1] + j) * d[0] + i] = (uint8_t)val;
            }
    return v;
}

static void tf_ramp(c5_tf_desc *t)
{
    memset(t, 0, sizeof *t);
    t->n_opacity = 4;
    double op[4][2] = {{0, 0}, {40, 0}, {150, 0.2}, {255, 0.9}};
    memcpy(t->opacity, op, sizeof op);
    t->n_color = 3;
    double co[3][4] = {{0, 1, 0, 0}, {128, 0.2, 0.9, 0.3}, {255, 1, 1, 1}};
    memcpy(t->color, co, sizeof co);
    t->ambient = 0.3, t->diffuse = 0.6, t->specular = 0.3, t->specular_power = 20;
}

typedef struct {
    c5_cast_volume *v;
    c5_cast_tf tf;
} fixture;

static int fixture_make(fixture *fx, const size_t d[3], const double sp[3], uint64_t seed)
{
    c5_err err;
    uint8_t *vox = blobs(d, seed);
    c5_tf_desc t;
    tf_ramp(&t);
    int rc = c5_cast_volume_make(vox, d, sp, &fx->v, &err) || c5_cast_volume_normals(fx->v, &err) ||
             c5_cast_tf_build(&t, fmin(sp[0], fmin(sp[1], sp[2])) * 0.8, 1, &fx->tf, &err);
    free(vox);
    if (rc)
        c5t_failf(__FILE__, __LINE__, "fixture: %s", err.msg);
    return rc;
}

/* The blobs fixture the rendering tests share: 45 x 38 x 29 voxels, anisotropic spacing, and
 * the point their cameras look at. */
static const size_t blob_dims[3] = {45, 38, 29};
static const double blob_spacing[3] = {1, 1.25, 1.5}, blob_focal[3] = {22, 23.1, 21};

static int render(const fixture *fx, const c5_cast_camera *cam, int w, int h, const c5_cast_opts *o, c5_image *img,
                  c5_cast_stats *st)
{
    c5_err err;
    img->rgb = NULL;
    if (c5_cast_render(fx->v, &fx->tf, cam, w, h, o, img, st, &err)) {
        c5t_failf(__FILE__, __LINE__, "render: %s", err.msg);
        return -1;
    }
    return 0;
}

static int differ(const c5_image *a, const c5_image *b)
{
    return memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * (size_t)a->h) != 0;
}

/* Fraction of pixels that are not black. */
static double coverage(const c5_image *a)
{
    size_t n = 0, all = (size_t)a->w * (size_t)a->h;
    for (size_t i = 0; i < all; i++)
        n += a->rgb[3 * i] != 0 || a->rgb[3 * i + 1] != 0 || a->rgb[3 * i + 2] != 0;
    return (double)n / (double)all;
}

TEST(cast_modes_draw_the_bits_of_plain)
{
    fixture fx;
    if (fixture_make(&fx, blob_dims, blob_spacing, 7))
        return;
    double views[3][3] = {{90, -60, 50}, {22.3, 23.1, 120}, {-20, 40, -35}};
    int n_diff = 0, n_cases = 0, n_sub = 0;
    for (int vi = 0; vi < 3; vi++) {
        c5_cast_camera cam;
        look_at(&cam, views[vi], blob_focal, 35);
        for (int shading = 0; shading < 2; shading++) {
            c5_cast_opts o;
            c5_cast_opts_default(&o);
            o.mode = C5_CAST_PLAIN, o.workers = 1, o.shading = shading;
            c5_image ref, img;
            c5_cast_stats st_ref, st;
            if (render(&fx, &cam, 53, 37, &o, &ref, &st_ref))
                return;
            CHECK(st_ref.samples_sub == 0); /* plain drops nothing */
            CHECK_MSG(coverage(&ref) > 0.05 && coverage(&ref) < 0.95, "view %d: coverage %.3f", vi, coverage(&ref));
            for (int mode = C5_CAST_ESS; mode < C5_CAST_MODES; mode++)
                for (int k = 0; k <= 16; k = k ? 2 * k : 1) {
                    o.mode = (c5_cast_mode)mode, o.k = k;
                    o.workers = 1 + (k % 3), o.queue_depth = 1 + k % 5;
                    o.prefetch = (c5_cast_prefetch)((k + mode) % C5_CAST_PREFETCHES);
                    o.sub_bricks = !(k & 2), o.self_produce = !(k & 4);
                    o.producer = k == 4 ? 1 : k & 9 ? 0 : -1; /* 0 only where the workers self-produce */
                    if (render(&fx, &cam, 53, 37, &o, &img, &st))
                        return;
                    n_cases++;
                    n_sub += st.samples_sub > 0;
                    /* every tile produced exactly once (53x37: 4x3 tiles), by the workers only when allowed */
                    CHECK_INT((int)st.tiles, 12);
                    CHECK(o.self_produce || st.tiles_self == 0);
                    CHECK(o.producer != 0 || (st.tiles_self == 12 && !st.producer));
                    /* one producer ray per pixel (ess) or per corner of the frame's k-grid: the
                     * corners on tile borders walked once, whichever tile got there first (this
                     * fixture's lists all fit in a shared entry) */
                    int kk = (int)st.k, cols = (53 + kk - 1) / kk + 1, rows = (37 + kk - 1) / kk + 1;
                    CHECK_MSG(st.producer_rays == (mode == C5_CAST_ESS ? 53u * 37u : (uint64_t)cols * (uint64_t)rows),
                              "mode %s k %d: %llu producer rays", c5_cast_mode_name(o.mode), kk,
                              (unsigned long long)st.producer_rays);
                    if (differ(&ref, &img)) {
                        n_diff++;
                        c5t_failf(__FILE__, __LINE__, "view %d shading %d mode %s k %d: image differs from plain", vi,
                                  shading, c5_cast_mode_name(o.mode), k);
                    }
                    /* the skipping modes took no more samples (ess strictly fewer); zero-opacity ones are all they dropped */
                    if (st.samples > st_ref.samples || (mode == C5_CAST_ESS && st.samples == st_ref.samples) || st.samples - st.samples_zero != st_ref.samples - st_ref.samples_zero)
                        c5t_failf(__FILE__, __LINE__, "view %d mode %s k %d: samples %llu (non-zero %llu) vs plain %llu (%llu)",
                                  vi, c5_cast_mode_name(o.mode), k, (unsigned long long)st.samples,
                                  (unsigned long long)(st.samples - st.samples_zero), (unsigned long long)st_ref.samples,
                                  (unsigned long long)(st_ref.samples - st_ref.samples_zero));
                    c5_image_free(&img);
                }
            c5_image_free(&ref);
        }
    }
    c5_cast_volume_free(fx.v);
    CHECK_INT(n_diff, 0);
    CHECK(n_cases == 3 * 2 * 3 * 6);
    CHECK(n_sub > 0); /* the sub-bricks did drop samples, yet the images are the same */
}

/* Refining only ever drops samples of bricks the octree calls empty, and it does drop some. */
TEST(cast_refine_drops_samples)
{
    size_t d[3] = {64, 64, 64};
    double sp[3] = {1, 1, 1};
    fixture fx;
    if (fixture_make(&fx, d, sp, 3))
        return;
    c5_cast_camera cam;
    double eye[3] = {180, -120, 90}, c[3] = {31.5, 31.5, 31.5};
    look_at(&cam, eye, c, 30);
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    c5_image a, b;
    c5_cast_stats sa, sb;
    o.mode = C5_CAST_APPROX, o.k = 8;
    if (render(&fx, &cam, 64, 64, &o, &a, &sa))
        return;
    o.mode = C5_CAST_APPROX_REFINE;
    if (render(&fx, &cam, 64, 64, &o, &b, &sb))
        return;
    CHECK(!differ(&a, &b));
    CHECK(sb.samples_hashed > 0);
    CHECK(sb.samples + sb.samples_sub + sb.samples_hashed == sa.samples + sa.samples_sub);
    /* with sub-bricks the hash drops nothing they keep: it drops only samples in bricks the
     * TF leaves empty (docs/caster.md), and all of such a brick's sub-bricks are empty */
    CHECK(sb.samples == sa.samples);
    c5_image_free(&a);
    c5_image_free(&b);
    o.sub_bricks = 0; /* without them it is what drops samples */
    if (render(&fx, &cam, 64, 64, &o, &b, &sb))
        return;
    o.mode = C5_CAST_APPROX;
    if (render(&fx, &cam, 64, 64, &o, &a, &sa))
        return;
    CHECK(!differ(&a, &b));
    CHECK(sb.samples < sa.samples && sb.samples_hashed > 0 && sb.samples_sub == 0);
    CHECK(sb.producer_rays == sa.producer_rays);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_cast_volume_free(fx.v);
}

/* The paper's Figure 7: a non-empty brick that no corner ray crosses. Searched for, not
 * assumed: with k = 16 and a far camera, the corner rays are several bricks apart. */
TEST(cast_figure7_missed_brick_is_still_drawn)
{
    size_t d[3] = {97, 97, 97};
    double sp[3] = {1, 1, 1};
    uint8_t *vox = calloc(d[0] * d[1] * d[2], 1);
    c5_cast_volume *probe;
    c5_err err;
    c5_tf_desc t;
    tf_ramp(&t);
    c5_cast_tf tf;
    CHECK(!c5_cast_tf_build(&t, 1, 1, &tf, &err));
    c5_cast_camera cam;
    double eye[3] = {48 + 20, 48 - 400, 48 + 15}, c[3] = {48, 48, 48};
    look_at(&cam, eye, c, 30);
    int w = 64, h = 64, k = 16;
    /* candidate bricks: interior ones; for each, fill only its inner voxels (so that no
     * neighbour brick becomes non-empty), and ask the producer's own walk whether a corner
     * ray reaches it undilated and whether some pixel centre ray does */
    int found = -1;
    double zero[3] = {0, 0, 0};
    for (int b = 0; b < 12 * 12 * 12 && found < 0; b++) {
        int bx = b % 12, by = b / 12 % 12, bz = b / 144;
        memset(vox, 0, d[0] * d[1] * d[2]);
        for (int z = 1; z < 8; z++)
            for (int y = 1; y < 8; y++)
                for (int x = 1; x < 8; x++)
                    vox[((size_t)(bz * 8 + z) * d[1] + (size_t)(by * 8 + y)) * d[0] + (size_t)(bx * 8 + x)] = 255;
        CHECK(!c5_cast_volume_make(vox, d, sp, &probe, &err));
        c5_cast_view vw = {.v = probe, .tf = &tf, .cam = &cam, .w = w, .h = h, .k = k, .step = 1,
                           .two_over_w = 2.0 / w, .two_over_h = 2.0 / h};
        for (int a = 0; a < 3; a++)
            vw.eye_v[a] = eye[a];
        CHECK(!c5_cast_view_classify(&vw, 0));
        double t0[64], t1[64], dir[3];
        int corner_hits = 0, pixel_hits = 0;
        for (int y = 0; y <= h; y += k)
            for (int x = 0; x <= w; x += k) {
                c5_cast_ray_dir(&vw, x, y, dir);
                corner_hits += c5_cast_ray_segments(&vw, dir, zero, t0, t1, 64, NULL) > 0;
            }
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                c5_cast_ray_dir(&vw, x + 0.5, y + 0.5, dir);
                pixel_hits += c5_cast_ray_segments(&vw, dir, zero, t0, t1, 64, NULL) > 0;
            }
        c5_cast_view_release(&vw);
        c5_cast_volume_free(probe);
        if (!corner_hits && pixel_hits >= 4)
            found = b;
    }
    CHECK_MSG(found >= 0, "no brick that only pixel rays cross: the construction failed");
    /* vox holds that brick now: draw it in every mode at this k */
    c5_cast_volume *v;
    CHECK(!c5_cast_volume_make(vox, d, sp, &v, &err));
    free(vox);
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    o.k = k;
    c5_image ref = {0}, img = {0};
    c5_cast_stats st;
    o.mode = C5_CAST_PLAIN;
    CHECK(!c5_cast_render(v, &tf, &cam, w, h, &o, &ref, &st, &err));
    CHECK_MSG(coverage(&ref) > 0, "the brick is not visible at all");
    for (int mode = C5_CAST_APPROX; mode < C5_CAST_MODES; mode++) {
        o.mode = (c5_cast_mode)mode;
        CHECK(!c5_cast_render(v, &tf, &cam, w, h, &o, &img, &st, &err));
        CHECK_MSG(!differ(&ref, &img), "mode %s dropped the brick no corner ray crosses", c5_cast_mode_name(o.mode));
        CHECK(st.k == k);
        c5_image_free(&img);
    }
    c5_image_free(&ref);
    c5_cast_volume_free(v);
}

/* Bricks that alternate along x: one of each three holds a stripe (voxels 2..5 of every 24), so
 * a ray along x meets more separate segments than a shared corner entry keeps (cast_corners.c). */
static c5_cast_volume *stripes(void)
{
    size_t d[3] = {449, 17, 17};
    double sp[3] = {1, 1, 1};
    uint8_t *vox = calloc(d[0] * d[1] * d[2], 1);
    for (size_t z = 0; z < d[2]; z++)
        for (size_t y = 0; y < d[1]; y++)
            for (size_t x = 0; x < d[0]; x++)
                if (x % 24 >= 2 && x % 24 <= 5)
                    vox[(z * d[1] + y) * d[0] + x] = 200;
    c5_cast_volume *v = NULL;
    c5_err err;
    if (c5_cast_volume_make(vox, d, sp, &v, &err))
        c5t_failf(__FILE__, __LINE__, "stripes: %s", err.msg);
    free(vox);
    return v;
}

/* A corner ray whose list is too long for the shared entry is walked again by each tile that
 * needs it, and the image is still plain's. */
TEST(cast_long_corner_lists_are_walked_again)
{
    c5_cast_volume *v = stripes();
    if (!v)
        return;
    c5_err err;
    c5_tf_desc t;
    tf_ramp(&t);
    c5_cast_tf tf;
    CHECK(!c5_cast_tf_build(&t, 1, 50, &tf, &err)); /* faint: every stripe shows through */
    c5_cast_camera cam;
    double eye[3] = {-300, 8.3, 8.6}, c[3] = {224, 8, 8};
    look_at(&cam, eye, c, 1);
    int w = 32, h = 32;
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    c5_image ref = {0}, img = {0};
    c5_cast_stats st;
    o.mode = C5_CAST_PLAIN;
    CHECK(!c5_cast_render(v, &tf, &cam, w, h, &o, &ref, &st, &err));
    CHECK_MSG(coverage(&ref) > 0.5, "coverage %.3f", coverage(&ref));
    for (int mode = C5_CAST_APPROX; mode < C5_CAST_MODES; mode++) {
        o.mode = (c5_cast_mode)mode, o.k = 16; /* 2 x 2 tiles of one subtile: all 9 corners shared */
        CHECK(!c5_cast_render(v, &tf, &cam, w, h, &o, &img, &st, &err));
        CHECK_MSG(!differ(&ref, &img), "mode %s", c5_cast_mode_name(o.mode));
        /* the 4 corners of the image walked once, the 4 edge middles twice and the centre 4
         * times (the dilation, 4.6 voxels, leaves the bricks apart) */
        CHECK_MSG(st.producer_rays == 4 + 4 * 2 + 4, "mode %s: %llu rays", c5_cast_mode_name(o.mode),
                  (unsigned long long)st.producer_rays);
        c5_image_free(&img);
    }
    c5_image_free(&ref);
    c5_cast_volume_free(v);
}

/* Tiles whose border corners come from the shared entries hold the bits of tiles that walked
 * every corner themselves: lists, hash bits; and only the corners that did not fit were walked
 * twice. Tiles produced backwards, so most take their corners from tiles produced earlier. */
static void same_tasks_shared_or_not(const c5_cast_volume *v, const c5_cast_tf *tf, const c5_cast_camera *cam,
                                     int k, int expect_all_kept)
{
    int w = 48, h = 40, ntx = 3; /* 3 x 3 tiles */
    c5_cast_view vw = {.v = v, .tf = tf, .cam = cam, .w = w, .h = h, .k = k, .mode = C5_CAST_APPROX_REFINE,
                       .step = 1, .margin_t = 0.01, .two_over_w = 2.0 / w, .two_over_h = 2.0 / h,
                       .hash_r = {3, 517, 1000}};
    for (int a = 0; a < 3; a++)
        vw.eye_v[a] = cam->eye[a] / v->spacing[a], vw.delta_v[a] = 0.5;
    if (c5_cast_view_classify(&vw, 1)) {
        c5t_failf(__FILE__, __LINE__, "classify: out of memory");
        return;
    }
    c5_cast_scratch *rs = c5_cast_scratch_new();
    c5_cast_task own[9] = {0}, shared[9] = {0};
    uint64_t rays_own = 0, rays_shared = 0;
    for (int i = 0; i < 9; i++) {
        own[i].hash = malloc(sizeof *own[i].hash * C5_CAST_TILE * C5_CAST_TILE);
        shared[i].hash = malloc(sizeof *shared[i].hash * C5_CAST_TILE * C5_CAST_TILE);
        CHECK(!c5_cast_produce(&vw, rs, i % ntx * C5_CAST_TILE, i / ntx * C5_CAST_TILE, &own[i]));
        rays_own += own[i].rays;
    }
    vw.corners = c5_cast_corners_new(w, h, k);
    for (int i = 8; i >= 0; i--) {
        CHECK(!c5_cast_produce(&vw, rs, i % ntx * C5_CAST_TILE, i / ntx * C5_CAST_TILE, &shared[i]));
        rays_shared += shared[i].rays;
    }
    int n_diff = 0;
    for (int i = 0; i < 9; i++) {
        int units = own[i].units_x * own[i].units_y;
        CHECK_INT(shared[i].units_x * shared[i].units_y, units);
        n_diff += memcmp(own[i].first, shared[i].first, sizeof own[i].first[0] * (size_t)(units + 1)) != 0;
        n_diff += memcmp(own[i].seg, shared[i].seg, sizeof own[i].seg[0] * own[i].first[units]) != 0;
        n_diff += memcmp(own[i].hash, shared[i].hash, sizeof own[i].hash[0] * (size_t)units) != 0;
        free(own[i].seg), free(own[i].hash), free(shared[i].seg), free(shared[i].hash);
    }
    CHECK_MSG(n_diff == 0, "k %d: %d tasks differ", k, n_diff);
    /* unshared, every tile walks its own corners (the last row of tiles is 8 pixels high);
     * shared, each corner of the frame is walked once */
    int per = C5_CAST_TILE / k + 1, last = (h - 2 * C5_CAST_TILE + k - 1) / k + 1;
    int cols = (w + k - 1) / k + 1, rows = (h + k - 1) / k + 1;
    CHECK_INT((int)rays_own, ntx * per * (2 * per + last));
    if (expect_all_kept)
        CHECK_MSG((int)rays_shared == cols * rows, "k %d: %d rays, %d corners", k, (int)rays_shared, cols * rows);
    else
        CHECK_MSG((int)rays_shared > cols * rows && rays_shared <= rays_own, "k %d: %d rays, %d corners, %d unshared",
                  k, (int)rays_shared, cols * rows, (int)rays_own);
    c5_cast_corners_free(vw.corners);
    vw.corners = NULL;
    c5_cast_view_release(&vw);
    c5_cast_scratch_free(rs);
}

TEST(cast_shared_corners_give_the_tasks_of_walking_each)
{
    size_t d[3] = {64, 64, 64};
    double sp[3] = {1, 1, 1};
    fixture fx;
    if (fixture_make(&fx, d, sp, 5))
        return;
    c5_cast_camera cam;
    double eye[3] = {150, -90, 120}, c[3] = {31.5, 31.5, 31.5};
    look_at(&cam, eye, c, 30);
    for (int k = 1; k <= 16; k *= 2)
        same_tasks_shared_or_not(fx.v, &fx.tf, &cam, k, 1);
    c5_cast_volume_free(fx.v);
    /* the stripes: lists too long to keep, walked again */
    c5_cast_volume *v = stripes();
    double se[3] = {-300, 8.3, 8.6}, scen[3] = {224, 8, 8};
    look_at(&cam, se, scen, 1);
    for (int k = 2; v && k <= 16; k *= 2)
        same_tasks_shared_or_not(v, &fx.tf, &cam, k, 0);
    c5_cast_volume_free(v);
}

/* Every octree node's min and max are those of the voxels its bricks' cells reach. */
TEST(cast_octree_minmax)
{
    size_t d[3] = {37, 20, 9};
    double sp[3] = {1, 1, 1};
    uint64_t s = 11;
    uint8_t *vox = malloc(d[0] * d[1] * d[2]);
    for (size_t i = 0; i < d[0] * d[1] * d[2]; i++)
        vox[i] = (uint8_t)(c5_splitmix64(&s) >> 56);
    c5_cast_volume *v;
    c5_err err;
    CHECK(!c5_cast_volume_make(vox, d, sp, &v, &err));
    CHECK_INT(v->nb[0], 5);
    CHECK_INT(v->nb[1], 3);
    CHECK_INT(v->nb[2], 1);
    for (int l = 0; l < v->levels; l++) {
        int side = C5_CAST_BRICK << l;
        for (int z = 0; z < v->ln[l][2]; z++)
            for (int y = 0; y < v->ln[l][1]; y++)
                for (int x = 0; x < v->ln[l][0]; x++) {
                    unsigned lo = 255, hi = 0;
                    for (size_t k = (size_t)z * side; k <= (size_t)(z + 1) * side && k < d[2]; k++)
                        for (size_t j = (size_t)y * side; j <= (size_t)(y + 1) * side && j < d[1]; j++)
                            for (size_t i = (size_t)x * side; i <= (size_t)(x + 1) * side && i < d[0]; i++) {
                                unsigned q = vox[(k * d[1] + j) * d[0] + i];
                                lo = q < lo ? q : lo, hi = q > hi ? q : hi;
                            }
                    const uint8_t *mm = v->minmax[l] + 2 * (((size_t)z * v->ln[l][1] + y) * v->ln[l][0] + x);
                    CHECK_MSG(mm[0] == lo && mm[1] == hi, "level %d node %d,%d,%d: %u..%u, expected %u..%u", l, x,
                              y, z, mm[0], mm[1], lo, hi);
                }
    }
    CHECK_INT(v->ln[v->levels - 1][0] * v->ln[v->levels - 1][1] * v->ln[v->levels - 1][2], 1);
    free(vox);
    c5_cast_volume_free(v);
}

/* Emptiness of a scalar range agrees with the table it summarises, for every range. */
TEST(cast_tf_emptiness)
{
    c5_tf_desc t;
    tf_ramp(&t);
    c5_cast_tf tf;
    c5_err err;
    CHECK(!c5_cast_tf_build(&t, 1, 1, &tf, &err));
    for (unsigned lo = 0; lo < 256; lo += 3)
        for (unsigned hi = lo; hi < 256; hi += 5) {
            int empty = 1;
            for (unsigned i = lo * C5_CAST_TF_SCALE; i <= hi * C5_CAST_TF_SCALE; i++)
                empty &= tf.rgba[i][3] == 0;
            CHECK_MSG(c5_cast_tf_empty(&tf, lo, hi) == empty, "range %u..%u", lo, hi);
        }
    CHECK(c5_cast_tf_empty(&tf, 0, 40));
    CHECK(!c5_cast_tf_empty(&tf, 0, 41));
    int lit_bad = 0, lit_n = 0; /* the eight-sample loop's byte table says the same */
    for (int i = 0; i < C5_CAST_TF_N; i++)
        lit_bad += tf.lit[i] != (tf.rgba[i][3] != 0), lit_n += tf.lit[i];
    CHECK_INT(lit_bad, 0);
    CHECK(lit_n > 0 && lit_n < C5_CAST_TF_N && !tf.lit[C5_CAST_TF_N] && !tf.lit[C5_CAST_TF_N + 2]);
    /* opacity correction: a = 1 - (1 - a_tf)^(step/unit) */
    CHECK(!c5_cast_tf_build(&t, 2, 1, &tf, &err));
    CHECK(fabs(tf.rgba[255 * C5_CAST_TF_SCALE][3] - (1 - 0.1 * 0.1)) < 1e-6);
}

TEST(cast_normal_codes_round_trip)
{
    uint64_t s = 5;
    for (int i = 0; i < 2000; i++) {
        double g[3] = {c5_uniform(&s) - 0.5, c5_uniform(&s) - 0.5, c5_uniform(&s) - 0.5}, n[3];
        double len = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        c5_cast_normal_decode(c5_cast_normal_encode(g[0], g[1], g[2]), n);
        double cosang = (n[0] * g[0] + n[1] * g[1] + n[2] * g[2]) / len;
        CHECK_MSG(cosang > cos(2.0 * M_PI / 180), "direction %d off by %.2f degrees", i, acos(cosang) * 180 / M_PI);
    }
    CHECK_INT(c5_cast_normal_encode(0, 0, 0), C5_CAST_NZERO);
}

/* A volume without thickness, a camera inside the volume, and bad arguments. */
TEST(cast_edges)
{
    c5_err err;
    c5_tf_desc t;
    tf_ramp(&t);
    c5_cast_tf tf;
    CHECK(!c5_cast_tf_build(&t, 1, 1, &tf, &err));
    size_t flat[3] = {16, 16, 1};
    double sp[3] = {1, 1, 1};
    uint8_t vox[16 * 16];
    memset(vox, 200, sizeof vox);
    c5_cast_volume *v;
    CHECK(!c5_cast_volume_make(vox, flat, sp, &v, &err));
    c5_cast_camera cam;
    double eye[3] = {7.5, 7.5, 40}, c[3] = {7.5, 7.5, 0};
    look_at(&cam, eye, c, 30);
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    c5_image img = {0};
    c5_cast_stats st;
    CHECK(!c5_cast_render(v, &tf, &cam, 20, 20, &o, &img, &st, &err));
    CHECK(coverage(&img) == 0);
    c5_image_free(&img);
    c5_cast_volume_free(v);

    fixture fx;
    size_t d[3] = {40, 40, 40};
    if (fixture_make(&fx, d, sp, 9))
        return;
    double in[3] = {20, 19, 21}, to[3] = {0, 0, 0};
    look_at(&cam, in, to, 90);
    o.mode = C5_CAST_PLAIN;
    c5_image ref;
    if (render(&fx, &cam, 32, 32, &o, &ref, &st))
        return;
    o.mode = C5_CAST_APPROX_REFINE;
    if (render(&fx, &cam, 32, 32, &o, &img, &st))
        return;
    CHECK_MSG(!differ(&ref, &img), "camera inside the volume: approx+refine differs from plain");
    /* Proposition 1 does not hold inside the volume; the default k is still C5_CAST_K_LOW, and
     * the dilation keeps the image plain's */
    CHECK_INT(c5_cast_prop1_k(fx.v, &cam, 32, 32), 1);
    CHECK_INT(st.k, C5_CAST_K_LOW);
    c5_image_free(&img);

    o.workers = 0;
    CHECK(c5_cast_render(fx.v, &fx.tf, &cam, 32, 32, &o, &img, &st, &err) == -1 && strstr(err.msg, "workers"));
    o.workers = 2, o.k = 3;
    CHECK(c5_cast_render(fx.v, &fx.tf, &cam, 32, 32, &o, &img, &st, &err) == -1 && strstr(err.msg, "k must"));
    o.k = 0, o.producer = 0, o.self_produce = 0; /* nobody would produce */
    CHECK(c5_cast_render(fx.v, &fx.tf, &cam, 32, 32, &o, &img, &st, &err) == -1 && strstr(err.msg, "self_produce"));
    o.producer = 2, o.self_produce = 1;
    CHECK(c5_cast_render(fx.v, &fx.tf, &cam, 32, 32, &o, &img, &st, &err) == -1 && strstr(err.msg, "producer must"));
    o.producer = -1;
    o.k = 0, o.shading = 1;
    CHECK(c5_cast_render(fx.v, &fx.tf, &cam, 16, 32, &o, &ref, &st, &err) == -1 && strstr(err.msg, "32x32"));
    c5_image_free(&ref);
    c5_cast_volume *bare;
    size_t zero_dims[3] = {0, 4, 4};
    CHECK(c5_cast_volume_make(vox, zero_dims, sp, &bare, &err) == -1 && strstr(err.msg, "dims"));
    c5_cast_volume_free(fx.v);
}

/* The workers' samples (cast_sample.h): the SSE2 units give the scalar definition's cell and
 * fraction bits, sub-brick, in-brick offset, brick change, trilinear value and shading
 * factors, for rays that start outside, run backwards, sit on cell faces and reach far
 * indices (so both clamps act). */
TEST(cast_samples_match_the_scalar_definition)
{
    uint64_t st = 77;
    static uint8_t brick[C5_CAST_BSTRIDE];
    for (int i = 0; i < C5_CAST_BVOX; i++)
        brick[i] = (uint8_t)(c5_splitmix64(&st) >> 56);
    memset(brick + C5_CAST_BVOX, 0xee, C5_CAST_BSTRIDE - C5_CAST_BVOX); /* padding: must not matter */
    static uint16_t normals[C5_CAST_BSTRIDE];
    static float tab[C5_CAST_NCODES][2];
    for (int i = 0; i < C5_CAST_BVOX; i++)
        normals[i] = (uint16_t)(c5_splitmix64(&st) % C5_CAST_NCODES);
    for (int i = 0; i < C5_CAST_NCODES; i++)
        for (int c = 0; c < 2; c++)
            tab[i][c] = (float)((double)(c5_splitmix64(&st) >> 11) / 9007199254740992.0 * 1.5);
    int cells[3] = {255, 37, 8}, bad = 0, clamped = 0, tested = 0;
    c5_cast_ray r;
    for (int a = 0; a < 3; a++)
        r.hi[a] = c5_cast_clamp_hi(cells[a]);
    r.o[3] = r.d[3] = r.hi[3] = 0;
    for (int ray = 0; ray < 2000; ray++) {
        for (int a = 0; a < 3; a++) {
            double u = (double)(c5_splitmix64(&st) >> 11) / 9007199254740992.0;
            r.o[a] = (float)((u * 1.4 - 0.2) * cells[a]);
            if (ray % 7 == 0)
                r.o[a] = (float)(c5_splitmix64(&st) % (uint64_t)(cells[a] + 1)); /* on a cell face */
            r.d[a] = (float)((double)(c5_splitmix64(&st) >> 11) / 4503599627370496.0 - 1.0);
            if (ray % 5 == a)
                r.d[a] = 0; /* parallel to a face */
        }
        r.step = ray % 3 == 0 ? 1.0f : 0.37f;
        int last[3] = {-1, -1, -1};
        for (int32_t j = ray % 11 == 0 ? 100000 : 0, n = 0; n < 400; j++, n++) {
            int i[3];
            float f[3];
            c5_cast_pos_ref(&r, j, i, f);
            c5_cast_pos p = c5_cast_pos_at(&r, j);
            unsigned sub = 0;
            int off = 0;
            for (int a = 0; a < 3; a++) {
                float fa = c5_cast_pos_frac(p, a);
                bad += c5_cast_pos_cell(p, a) != i[a] || memcmp(&fa, &f[a], sizeof fa) != 0;
                bad += i[a] < 0 || i[a] >= cells[a] || !(f[a] >= 0 && f[a] < 1);
                clamped += i[a] == cells[a] - 1 && f[a] > 0.999f;
                sub |= (unsigned)(i[a] / C5_CAST_SUB & 1) << a;
            }
            off = i[0] % C5_CAST_BRICK + C5_CAST_BSIDE * (i[1] % C5_CAST_BRICK) +
                  C5_CAST_BSIDE * C5_CAST_BSIDE * (i[2] % C5_CAST_BRICK);
            bad += c5_cast_pos_sub(p) != sub || c5_cast_pos_off(p) != off;
            float v = c5_cast_tri(brick + off, p), vr = c5_cast_tri_ref(brick + off, f);
            bad += memcmp(&v, &vr, sizeof v) != 0;
            float k[2], kr[2];
            c5_cast_light kl = c5_cast_shade(tab, normals + off, p);
            k[0] = c5_cast_light_factor(kl, 0), k[1] = c5_cast_light_factor(kl, 1);
            c5_cast_shade_ref(tab, normals + off, f, kr);
            bad += memcmp(k, kr, sizeof k) != 0;
            int moved = 0;
            for (int a = 0; a < 3; a++)
                moved |= i[a] / C5_CAST_BRICK != last[a];
            c5_cast_bkey prev = c5_cast_pos_bkey(c5_cast_pos_at(&r, j > 0 ? j - 1 : 0));
            if (n > 0)
                bad += c5_cast_bkey_eq(c5_cast_pos_bkey(p), prev) == moved;
            for (int a = 0; a < 3; a++)
                last[a] = i[a] / C5_CAST_BRICK;
            tested++;
        }
    }
    CHECK_INT(bad, 0);
    CHECK(tested == 2000 * 400 && clamped > 0);
}

/* One pixel as the definitions say, sample by sample: every sample j of the ray inside the
 * volume at its cell and fraction (c5_cast_pos_ref), trilinear value, TF entry, headlight
 * factors, shaded colour and front-to-back compositing, zero-opacity samples included, to
 * early termination. Adds its samples to *n, its zero-opacity ones to *zero, and 1 to *term
 * when it terminated. */
static void march_definition(const c5_cast_view *vw, int px, int py, float rgb[3], uint64_t *n, uint64_t *zero,
                             uint64_t *term)
{
    const c5_cast_volume *v = vw->v;
    float acc[4] = {0, 0, 0, 0};
    c5_cast_ray r;
    int32_t jin, jout;
    for (int32_t j = c5_cast_pixel_ray(vw, px, py, &r, &jin, &jout) ? jin : 1, j1 = j == 1 ? 0 : jout; j <= j1; j++) {
        int i[3];
        float f[3];
        c5_cast_pos_ref(&r, j, i, f);
        size_t bi = c5_cast_brick_index(v, i[0] / C5_CAST_BRICK, i[1] / C5_CAST_BRICK, i[2] / C5_CAST_BRICK);
        int off = i[0] % C5_CAST_BRICK + C5_CAST_DY * (i[1] % C5_CAST_BRICK) + C5_CAST_DZ * (i[2] % C5_CAST_BRICK);
        float sv = c5_cast_tri_ref(v->bricks + bi * C5_CAST_BSTRIDE + off, f);
        const float *e = vw->tf->rgba[(int)(sv * C5_CAST_TF_SCALE + 0.5f)];
        float c[4] = {e[0], e[1], e[2], e[3]};
        if (vw->shading) {
            float k[2];
            c5_cast_shade_ref(vw->shade, v->normals + bi * C5_CAST_BSTRIDE + off, f, k);
            c5_cast_lit_ref(e, k, c);
        }
        c5_cast_over_ref(acc, c);
        (*n)++, *zero += e[3] == 0;
        if (vw->early && acc[3] > C5_CAST_OPAQUE) {
            (*term)++;
            break;
        }
    }
    memcpy(rgb, acc, 3 * sizeof *rgb);
}

/* The workers march in stages over batches of samples (cast_worker.c) and leave out the
 * zero-opacity ones: still the definition's bits per pixel, its sample and zero-opacity counts
 * and its terminated rays, shaded and not; and the counts of dropped samples stop where the
 * ray does. The fixture's blobs stop some rays early and others pass through, so batches end
 * both ways. */
TEST(cast_workers_composite_as_the_definition)
{
    fixture fx;
    if (fixture_make(&fx, blob_dims, blob_spacing, 11))
        return;
    c5_tf_desc t; /* the fixture's TF, denser: opaque enough to stop rays in the blobs */
    tf_ramp(&t);
    t.opacity[2][1] = 0.9, t.opacity[3][1] = 1;
    c5_err err;
    if (c5_cast_tf_build(&t, 1, 1, &fx.tf, &err)) {
        c5t_failf(__FILE__, __LINE__, "tf: %s", err.msg);
        c5_cast_volume_free(fx.v);
        return;
    }
    double views[2][3] = {{90, -60, 50}, {-20, 40, -35}};
    int w = 53, h = 37, bad = 0, wides = 1 + c5_cast_wide_usable(fx.v);
    uint64_t terminated = 0;
    /* shaded and not, each in the SSE2 loop and, where the CPU has AVX2, the eight-sample one */
    for (int vi = 0; vi < 2; vi++)
        for (int pass = 0; pass < 2 * wides; pass++) {
            int shading = pass / wides, wide = pass % wides;
            c5_cast_camera cam;
            look_at(&cam, views[vi], blob_focal, 35);
            c5_cast_opts o;
            c5_cast_opts_default(&o);
            o.mode = C5_CAST_PLAIN, o.workers = 2, o.shading = shading, o.wide = wide;
            c5_image img;
            c5_cast_stats st;
            c5_cast_view vw;
            if (render(&fx, &cam, w, h, &o, &img, &st))
                return;
            if (c5_cast_view_setup(&vw, fx.v, &fx.tf, &cam, w, h, &o, &err)) {
                c5t_failf(__FILE__, __LINE__, "view: %s", err.msg);
                c5_cast_view_release(&vw);
                c5_image_free(&img);
                return;
            }
            uint64_t n = 0, zero = 0, term = 0;
            for (int py = 0; py < h; py++)
                for (int px = 0; px < w; px++) {
                    float rgb[3];
                    march_definition(&vw, px, py, rgb, &n, &zero, &term);
                    bad += memcmp(rgb, img.rgb + 3 * ((size_t)py * w + px), sizeof rgb) != 0;
                }
            CHECK(st.wide == wide);
            CHECK_MSG(st.samples == n && st.samples_zero == zero && st.rays_terminated == term,
                      "view %d shading %d: samples %llu/%llu zero %llu/%llu terminated %llu/%llu", vi, shading,
                      (unsigned long long)st.samples, (unsigned long long)n, (unsigned long long)st.samples_zero,
                      (unsigned long long)zero, (unsigned long long)st.rays_terminated, (unsigned long long)term);
            terminated += term;
            /* approx drops samples in empty sub-brick; up to where each ray ends, a dropped one
             * is one fewer marched, however the batches fall */
            c5_cast_stats sa, sb;
            c5_image ia, ib;
            o.mode = C5_CAST_APPROX, o.sub_bricks = 1;
            if (!render(&fx, &cam, w, h, &o, &ia, &sa)) {
                o.sub_bricks = 0;
                if (!render(&fx, &cam, w, h, &o, &ib, &sb)) {
                    CHECK(sa.samples_sub > 0 && sa.samples + sa.samples_sub == sb.samples && !differ(&ia, &img) &&
                          !differ(&ib, &img) && sa.rays_terminated == term && sb.rays_terminated == term);
                    c5_image_free(&ib);
                }
                c5_image_free(&ia);
            }
            c5_cast_view_release(&vw);
            c5_image_free(&img);
        }
    c5_cast_volume_free(fx.v);
    CHECK_INT(bad, 0);
    CHECK(terminated > 0);
}

/* The eight-sample loop (cast_wide.c) against the SSE2 one: the same image bits and the same
 * counts (samples, zero-opacity, dropped in empty sub-bricks, terminated) in every mode it runs
 * in, shaded and not, with sub-bricks on and off, early termination on and off, several k, steps
 * and worker counts; a dense TF ends rays inside batches. Where the CPU has no AVX2, wide 1 is
 * refused. */
TEST(cast_wide_loop_is_the_sse2_loop)
{
    fixture fx;
    if (fixture_make(&fx, blob_dims, blob_spacing, 5))
        return;
    c5_err err;
    if (!c5_cast_wide_usable(fx.v)) {
        c5_cast_opts o;
        c5_cast_opts_default(&o);
        o.wide = 1;
        c5_cast_camera cam;
        look_at(&cam, (double[3]){90, -60, 50}, blob_focal, 35);
        c5_image img = {0};
        c5_cast_stats st;
        CHECK(c5_cast_render(fx.v, &fx.tf, &cam, 16, 16, &o, &img, &st, &err) != 0);
        c5_image_free(&img);
        c5_cast_volume_free(fx.v);
        return;
    }
    c5_cast_tf dense;
    c5_tf_desc t;
    tf_ramp(&t);
    t.opacity[2][1] = 0.9, t.opacity[3][1] = 1;
    if (c5_cast_tf_build(&t, 0.6, 1, &dense, &err)) {
        c5t_failf(__FILE__, __LINE__, "tf: %s", err.msg);
        c5_cast_volume_free(fx.v);
        return;
    }
    double views[3][3] = {{90, -60, 50}, {22.3, 23.1, 120}, {-20, 40, -35}};
    int cases = 0, bad = 0;
    uint64_t terminated = 0, dropped = 0;
    for (int vi = 0; vi < 3; vi++)
        for (int c = 0; c < 48; c++) {
            c5_cast_camera cam;
            look_at(&cam, views[vi], blob_focal, 25 + 5 * vi);
            c5_cast_opts o;
            c5_cast_opts_default(&o);
            o.shading = c >= 24;
            o.mode = (c5_cast_mode)(c % 3); /* plain, ess, approx */
            o.sub_bricks = !(c & 4), o.early_termination = !(c & 8), o.k = c & 16 ? 8 : 0;
            o.workers = 1 + c % 2, o.step = c % 5 == 0 ? 0.6 : 0;
            o.prefetch = (c / 3) % 2 ? C5_CAST_PREFETCH_OFF : C5_CAST_PREFETCH_CELLS;
            c5_cast_tf *tf = c % 24 < 12 ? &fx.tf : &dense;
            c5_image a = {0}, b = {0};
            c5_cast_stats sa, sb;
            o.wide = 0;
            int rc = c5_cast_render(fx.v, tf, &cam, 61, 43, &o, &a, &sa, &err);
            o.wide = 1;
            rc = rc || c5_cast_render(fx.v, tf, &cam, 61, 43, &o, &b, &sb, &err);
            if (rc) {
                c5t_failf(__FILE__, __LINE__, "render: %s", err.msg);
                bad++;
            } else {
                cases++;
                int same = !differ(&a, &b) && sa.samples == sb.samples && sa.samples_zero == sb.samples_zero &&
                           sa.samples_sub == sb.samples_sub && sa.rays_terminated == sb.rays_terminated &&
                           sa.samples_hashed == sb.samples_hashed && !sa.wide && sb.wide;
                if (!same)
                    c5t_failf(__FILE__, __LINE__,
                              "view %d case %d (%s): samples %llu/%llu zero %llu/%llu sub %llu/%llu terminated "
                              "%llu/%llu, images %s",
                              vi, c, c5_cast_mode_name(o.mode), (unsigned long long)sa.samples,
                              (unsigned long long)sb.samples, (unsigned long long)sa.samples_zero,
                              (unsigned long long)sb.samples_zero, (unsigned long long)sa.samples_sub,
                              (unsigned long long)sb.samples_sub, (unsigned long long)sa.rays_terminated,
                              (unsigned long long)sb.rays_terminated, differ(&a, &b) ? "differ" : "same");
                bad += !same;
                terminated += sb.rays_terminated, dropped += sb.samples_sub;
            }
            c5_image_free(&a);
            c5_image_free(&b);
        }
    /* the refining hash and the brick prefetch stay on the SSE2 loop */
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    c5_cast_camera cam;
    look_at(&cam, views[0], blob_focal, 35);
    c5_image img = {0};
    c5_cast_stats st;
    o.wide = 1, o.mode = C5_CAST_APPROX_REFINE;
    if (!c5_cast_render(fx.v, &fx.tf, &cam, 16, 16, &o, &img, &st, &err))
        CHECK(!st.wide);
    c5_image_free(&img);
    o.mode = C5_CAST_APPROX, o.prefetch = C5_CAST_PREFETCH_BRICKS;
    if (!c5_cast_render(fx.v, &fx.tf, &cam, 16, 16, &o, &img, &st, &err))
        CHECK(!st.wide);
    c5_image_free(&img);
    c5_cast_volume_free(fx.v);
    CHECK_INT(bad, 0);
    CHECK_INT(cases, 3 * 48);
    CHECK(terminated > 0 && dropped > 0);
}

/* The volume keeps its last classification for the next frame with the same non-zero table
 * entries (c5_cast_view_classify). A frame with another table must not take it: a table that
 * makes more bricks non-empty, cast right after one that leaves them empty, still draws what a
 * fresh volume draws; so does a table with the same non-zero entries and other colours, and
 * two threads casting both tables at once on one volume. */
typedef struct {
    const c5_cast_volume *v;
    const c5_cast_tf *tf[2];
    const c5_image *ref[2];
    c5_cast_camera cam;
    int bad, done;
} kept_job;

static void *kept_thread(void *arg)
{
    kept_job *j = arg;
    for (int i = 0; i < 12; i++) {
        int t = (i + j->done) % 2; /* the two threads start on different tables */
        c5_cast_opts o;
        c5_cast_opts_default(&o);
        o.workers = 1;
        c5_image img = {0};
        c5_cast_stats st;
        c5_err err;
        if (c5_cast_render(j->v, j->tf[t], &j->cam, 40, 30, &o, &img, &st, &err) || differ(&img, j->ref[t]))
            j->bad++;
        c5_image_free(&img);
    }
    return NULL;
}

TEST(cast_kept_classification_is_only_for_its_table)
{
    fixture fx;
    if (fixture_make(&fx, blob_dims, blob_spacing, 3))
        return;
    c5_cast_volume *fresh[3] = {NULL, NULL, NULL};
    c5_cast_tf tfs[3];
    c5_tf_desc t;
    c5_err err;
    tf_ramp(&t);
    t.opacity[1][0] = 5; /* opaque from scalar 5: the noise field's bricks are no longer empty */
    int rc = c5_cast_tf_build(&t, 1, 1, &tfs[1], &err);
    tf_ramp(&t);
    t.color[0][1] = 0.2, t.color[2][3] = 0.4; /* the fixture's non-zero entries, other colours */
    rc = rc || c5_cast_tf_build(&t, 1, 1, &tfs[2], &err);
    tfs[0] = fx.tf;
    uint8_t *vox = blobs(blob_dims, 3);
    for (int i = 0; i < 3 && !rc; i++)
        rc = c5_cast_volume_make(vox, blob_dims, blob_spacing, &fresh[i], &err);
    free(vox);
    if (rc) {
        c5t_failf(__FILE__, __LINE__, "set-up: %s", err.msg);
        for (int i = 0; i < 3; i++)
            c5_cast_volume_free(fresh[i]);
        c5_cast_volume_free(fx.v);
        return;
    }
    c5_cast_camera cam;
    look_at(&cam, (double[3]){90, -60, 50}, blob_focal, 35);
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    c5_image ref[3] = {{0}}, img = {0};
    c5_cast_stats sref[3], st;
    for (int i = 0; i < 3; i++) /* each table on a volume of its own: nothing kept from another */
        render(&(fixture){fresh[i], tfs[i]}, &cam, 40, 30, &o, &ref[i], &sref[i]);
    CHECK(differ(&ref[0], &ref[1]) && sref[1].samples > sref[0].samples);
    /* one volume, the tables in turn: 0, 0 (kept), 1 (not 0's), 0, 2 (0's kept), 1 */
    static const int order[6] = {0, 0, 1, 0, 2, 1};
    for (int k = 0; k < 6; k++) {
        int i = order[k];
        if (render(&(fixture){fx.v, tfs[i]}, &cam, 40, 30, &o, &img, &st))
            break;
        CHECK_MSG(!differ(&img, &ref[i]) && st.samples == sref[i].samples && st.samples_sub == sref[i].samples_sub,
                  "step %d (table %d): samples %llu against %llu", k, i, (unsigned long long)st.samples,
                  (unsigned long long)sref[i].samples);
        c5_image_free(&img);
    }
    pthread_t th[2];
    kept_job jobs[2];
    for (int i = 0; i < 2; i++) {
        jobs[i] = (kept_job){.v = fx.v, .tf = {&tfs[0], &tfs[1]}, .ref = {&ref[0], &ref[1]}, .cam = cam, .done = i};
        pthread_create(&th[i], NULL, kept_thread, &jobs[i]);
    }
    for (int i = 0; i < 2; i++) {
        pthread_join(th[i], NULL);
        CHECK_INT(jobs[i].bad, 0);
    }
    for (int i = 0; i < 3; i++) {
        c5_image_free(&ref[i]);
        c5_cast_volume_free(fresh[i]);
    }
    c5_cast_volume_free(fx.v);
}
