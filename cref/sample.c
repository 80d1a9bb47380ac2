/* Trilinear reconstruction of the super volume and of its central-difference gradient
 * (docs/rendering-spec.md, sec. 3). */
#include "cref.h"
#include "trace.h"

#include <tgmath.h>

static long clampl(long i, size_t n) { return i < 0 ? 0 : i >= (long)n ? (long)n - 1 : i; }

void C5R(supervol_sample)(const c5_supervol *sv, c5_rvec3 p, c5_real *value, c5_rvec3 *grad)
{
    /* Continuous voxel coordinates, voxel centres at integers. */
    c5_real x = (p.x - sv->origin.x) / sv->spacing.x - 0.5;
    c5_real y = (p.y - sv->origin.y) / sv->spacing.y - 0.5;
    c5_real z = (p.z - sv->origin.z) / sv->spacing.z - 0.5;
    c5_real fx = floor(x), fy = floor(y), fz = floor(z);
    long i = (long)fx, j = (long)fy, k = (long)fz;
    c5_real tx = x - fx, ty = y - fy, tz = z - fz;
    c5_real v = 0, g[3] = {0, 0, 0};
    if (__builtin_expect(sv->v != NULL, 1)) {
        for (int c = 0; c < 8; c++) {
            int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
            c5_real w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
            /* Corners are clamped first: outside the outer voxel centres the field (value and
             * gradient) extends the edge voxel's, as if ghost voxels copied the edge. */
            long a = clampl(i + dx, sv->dims[0]), b = clampl(j + dy, sv->dims[1]), e = clampl(k + dz, sv->dims[2]);
            v += w * c5_supervol_at_resident(sv, a, b, e);
            if (grad) {
                g[0] += w * ((c5_real)c5_supervol_at_resident(sv, a + 1, b, e) - c5_supervol_at_resident(sv, a - 1, b, e));
                g[1] += w * ((c5_real)c5_supervol_at_resident(sv, a, b + 1, e) - c5_supervol_at_resident(sv, a, b - 1, e));
                g[2] += w * ((c5_real)c5_supervol_at_resident(sv, a, b, e + 1) - c5_supervol_at_resident(sv, a, b, e - 1));
            }
        }
    } else {
        /* Out of core: the same arithmetic on the same voxels, gathered in one read. Every
         * voxel read above lies in [clamp(i) - 1, clamp(i + 1) + 1] per axis (after its own
         * clamp), a box of 4^3 at most. */
        long lo[3] = {clampl(i, sv->dims[0]) - 1, clampl(j, sv->dims[1]) - 1, clampl(k, sv->dims[2]) - 1};
        long hi[3] = {lo[0] + 4, lo[1] + 4, lo[2] + 4};
        uint8_t nb[64];
        c5_supervol_read_box_or_exit(sv, lo, hi, nb);
#define NB(x, y, z)                                                                                                    \
    nb[((clampl(z, sv->dims[2]) - lo[2]) * 4 + clampl(y, sv->dims[1]) - lo[1]) * 4 + clampl(x, sv->dims[0]) - lo[0]]
        for (int c = 0; c < 8; c++) {
            int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
            c5_real w = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
            long a = clampl(i + dx, sv->dims[0]), b = clampl(j + dy, sv->dims[1]), e = clampl(k + dz, sv->dims[2]);
            v += w * (unsigned)NB(a, b, e);
            if (grad) {
                g[0] += w * ((c5_real)(unsigned)NB(a + 1, b, e) - (unsigned)NB(a - 1, b, e));
                g[1] += w * ((c5_real)(unsigned)NB(a, b + 1, e) - (unsigned)NB(a, b - 1, e));
                g[2] += w * ((c5_real)(unsigned)NB(a, b, e + 1) - (unsigned)NB(a, b, e - 1));
            }
        }
#undef NB
    }
    *value = v;
    if (grad)
        *grad = rv3(g[0] / (2 * (c5_real)sv->spacing.x), g[1] / (2 * (c5_real)sv->spacing.y),
                    g[2] / (2 * (c5_real)sv->spacing.z));
}
