#include "generators.h"

#include <math.h>
#include <string.h>

#include "rng.h"

double c5_marschner_lobb(double x, double y, double z, double f_m, double alpha)
{
    double r = sqrt(x * x + y * y);
    double rho_r = cos(2 * M_PI * f_m * cos(M_PI * r / 2));
    return (1 - sin(M_PI * z / 2) + alpha * (1 + rho_r)) / (2 * (1 + alpha));
}

void c5_marschner_lobb_grad(double x, double y, double z, double f_m, double alpha, double g[3])
{
    double r = sqrt(x * x + y * y);
    double k = 1 / (2 * (1 + alpha));
    /* d rho_r / dr; zero on the axis, where the field is smooth and symmetric. */
    double drdr = M_PI * M_PI * f_m * sin(M_PI * r / 2) * sin(2 * M_PI * f_m * cos(M_PI * r / 2));
    double s = r > 0 ? k * alpha * drdr / r : 0;
    g[0] = s * x;
    g[1] = s * y;
    g[2] = -k * (M_PI / 2) * cos(M_PI * z / 2);
}

static uint8_t quantise(double unit)
{
    double v = floor(unit * 255 + 0.5);
    return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
}

static double smoothstep(double e0, double e1, double x)
{
    double t = (x - e0) / (e1 - e0);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return t * t * (3 - 2 * t);
}

/* CT-like stand-in: a bright ellipsoidal shell (bone) around smooth Gaussian blobs of
 * mid-range tissue, so that a CT transfer function shows both. The shell's and the tissue's
 * edges rise over 0.06 of d, or over 6 voxels along the edge's normal when that is wider:
 * a scanner's blur. Sharper edges are not band-limited to the grid, and each voxel layer an
 * edge crosses then shows as a ring in the shading, whatever the gradient filter
 * (docs/accuracy.md, "Gradients"). vox[a]: a voxel's size along axis a in p (2 / dims). */
__attribute__((noinline)) static double blobs_value(const double p[3], const c5_gen_blob *b, int n,
                                                    const double vox[3])
{
    double r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2], d = sqrt(r2) / 0.92, h = 0.03;
    if (r2 > 0) {
        /* the voxel's extent along the normal p / |p|, in d */
        double e2 = 0;
        for (int a = 0; a < 3; a++)
            e2 += p[a] * p[a] * vox[a] * vox[a];
        double hv = 3 * sqrt(e2 / r2) / 0.92;
        h = hv > h ? hv : h;
    }
    double shell = smoothstep(0.83 - h, 0.83 + h, d) * (1 - smoothstep(0.97 - h, 0.97 + h, d));
    double tissue = 0;
    for (int i = 0; i < n; i++) {
        double dx = p[0] - b[i].c[0], dy = p[1] - b[i].c[1], dz = p[2] - b[i].c[2];
        tissue += b[i].amp * exp(-(dx * dx + dy * dy + dz * dz) * b[i].inv_s2);
    }
    tissue = fmin(tissue, 1) * (1 - smoothstep(0.81 - h, 0.81 + h, d));
    return fmax(shell * 0.9, tissue * 0.62);
}

static void voxel_size(const c5_volume_desc *d, double vox[3])
{
    for (int a = 0; a < 3; a++)
        vox[a] = 2.0 / (double)(d->gen_dims[a] ? d->gen_dims[a] : 1);
}

/* Value noise on an integer lattice, hashed from the seed. */
static double lattice(long x, long y, long z, uint64_t seed)
{
    uint64_t s = seed ^ ((uint64_t)x * 0x8CB92BA72F3D8DD7ull) ^ ((uint64_t)y * 0xD6E8FEB86659FD93ull) ^
                 ((uint64_t)z * 0xA0761D6478BD642Full);
    return c5_uniform(&s);
}

static double value_noise(double x, double y, double z, uint64_t seed)
{
    double fx = floor(x), fy = floor(y), fz = floor(z);
    long ix = (long)fx, iy = (long)fy, iz = (long)fz;
    double tx = smoothstep(0, 1, x - fx), ty = smoothstep(0, 1, y - fy), tz = smoothstep(0, 1, z - fz);
    double v = 0;
    for (int c = 0; c < 8; c++) {
        int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
        double w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
        v += w * lattice(ix + dx, iy + dy, iz + dz, seed);
    }
    return v;
}

static double cloud_value(double p[3], uint64_t seed)
{
    double fbm = 0, amp = 0.5, freq = 3;
    for (int o = 0; o < 4; o++, amp *= 0.5, freq *= 2)
        fbm += amp * value_noise(p[0] * freq + 17.1, p[1] * freq + 5.3, p[2] * freq + 9.7, seed + (uint64_t)o);
    double d = sqrt(p[0] * p[0] + p[1] * p[1] + 1.6 * p[2] * p[2]);
    double density = fbm * (1 - smoothstep(0.45, 0.95, d));
    return (density - 0.22) * 2.2;
}

double c5_gen_unit(const c5_volume_desc *d, const c5_gen_state *g, const double p[3])
{
    switch (d->generator) {
    case C5_GEN_MARSCHNER_LOBB: return c5_marschner_lobb(p[0], p[1], p[2], d->f_m, d->alpha);
    case C5_GEN_BLOBS: {
        double vox[3];
        voxel_size(d, vox);
        return blobs_value(p, g->blobs, g->n_blobs, vox);
    }
    case C5_GEN_CLOUD: {
        double q[3] = {p[0], p[1], p[2]};
        return cloud_value(q, d->seed);
    }
    default: return NAN;
    }
}

void c5_gen_prepare(const c5_volume_desc *d, c5_gen_state *g)
{
    g->n_blobs = 0;
    if (d->generator != C5_GEN_BLOBS)
        return;
    uint64_t st = d->seed;
    g->n_blobs = d->count < C5_GEN_MAX_BLOBS ? d->count : C5_GEN_MAX_BLOBS;
    for (int i = 0; i < g->n_blobs; i++) {
        double r = 0.55 * cbrt(c5_uniform(&st)), z = 1 - 2 * c5_uniform(&st), phi = 2 * M_PI * c5_uniform(&st);
        double s = sqrt(fmax(0, 1 - z * z)), sigma = 0.12 + 0.18 * c5_uniform(&st);
        c5_gen_blob *b = &g->blobs[i];
        b->c[0] = r * s * cos(phi);
        b->c[1] = r * s * sin(phi);
        b->c[2] = r * z;
        b->inv_s2 = 1 / (sigma * sigma);
        b->amp = 0.35 + 0.35 * c5_uniform(&st);
    }
}

void c5_generate_box(const c5_volume_desc *d, const c5_gen_state *g, const size_t lo[3], const size_t hi[3],
                     uint8_t *out, size_t sy, size_t sz)
{
    size_t nx = d->gen_dims[0], ny = d->gen_dims[1], nz = d->gen_dims[2];
    double rad = d->radius * (double)(nx < ny ? (nx < nz ? nx : nz) : (ny < nz ? ny : nz));
    /* locals: a store through out (uint8_t) could alias *d and *g for all the compiler knows */
    const c5_generator gen = d->generator;
    const double f_m = d->f_m, alpha = d->alpha, value = d->value;
    const uint64_t seed = d->seed;
    const int axis = d->axis, nb = g->n_blobs;
    double vox[3];
    voxel_size(d, vox);
    c5_gen_blob blobs[C5_GEN_MAX_BLOBS]; /* a local copy: known not to alias out */
    memcpy(blobs, g->blobs, sizeof blobs[0] * (size_t)(nb > 0 ? nb : 0));
    const size_t n_axis = d->gen_dims[axis < 0 || axis > 2 ? 0 : axis];
    for (size_t z = lo[2]; z < hi[2]; z++)
        for (size_t y = lo[1]; y < hi[1]; y++) {
            uint8_t *row = out + (z - lo[2]) * sz + (y - lo[1]) * sy - lo[0];
            for (size_t x = lo[0]; x < hi[0]; x++) {
                /* the voxel's own definition: nothing depends on the box */
                double p[3] = {2 * (x + 0.5) / nx - 1, 2 * (y + 0.5) / ny - 1, 2 * (z + 0.5) / nz - 1};
                double u = 0;
                switch (gen) {
                case C5_GEN_MARSCHNER_LOBB: u = c5_marschner_lobb(p[0], p[1], p[2], f_m, alpha); break;
                case C5_GEN_BLOBS: u = blobs_value(p, blobs, nb, vox); break;
                case C5_GEN_CLOUD: u = cloud_value(p, seed); break;
                case C5_GEN_SPHERE: {
                    /* Distance in voxels from the centre, with a one-voxel linear edge. */
                    double dx = x + 0.5 - nx / 2.0, dy = y + 0.5 - ny / 2.0, dz = z + 0.5 - nz / 2.0;
                    double e = rad - sqrt(dx * dx + dy * dy + dz * dz) + 0.5;
                    u = (e < 0 ? 0 : e > 1 ? 1 : e) * value / 255.0;
                    break;
                }
                case C5_GEN_CONSTANT: u = value / 255.0; break;
                case C5_GEN_RAMP: {
                    size_t idx[3] = {x, y, z};
                    u = (idx[axis] + 0.5) / (double)n_axis;
                    break;
                }
                }
                row[x] = quantise(u);
            }
        }
}

void c5_generate(const c5_volume_desc *d, uint8_t *out)
{
    c5_gen_state g;
    c5_gen_prepare(d, &g);
    size_t lo[3] = {0, 0, 0};
    c5_generate_box(d, &g, lo, d->gen_dims, out, d->gen_dims[0], d->gen_dims[0] * d->gen_dims[1]);
}

const char *c5_generators_build(void) { return __DATE__ " " __TIME__; }

const char *c5_generator_name(c5_generator g)
{
    static const char *names[] = {"marschner_lobb", "blobs", "cloud", "sphere", "constant", "ramp"};
    return (unsigned)g < sizeof names / sizeof names[0] ? names[g] : "?";
}
