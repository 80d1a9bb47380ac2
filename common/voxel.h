/* What every volume reader shares (volume.c, nrrd_precheck.c, voxsrc.c, supervol.c): the
 * voxel types a file may hold, the extents accepted, and the checked opening of a file. */
#ifndef C5_VOXEL_H
#define C5_VOXEL_H

#include <stddef.h>

#include "err.h"

typedef enum { C5_VOX_NONE = 0, C5_VOX_U8 = 1, C5_VOX_U16 = 2 } c5_voxel_type;

/* Largest accepted extent per axis and in total. Per axis: the scene format's and the scene
 * descriptor's 16 bits. In total 2^44 voxels (16 TiB of 8-bit voxels; 16384^3 and 65535^2 x
 * 4096 pass): a volume is never held whole unless it fits the memory budget (supervol.h), so
 * the bound is file offsets and voxel indices far inside 64 bits, not this host's memory
 * (docs/out-of-core.md). c5_volume_load, which does read a whole file, is used only where its
 * caller bounds the size (cube5 cast). */
#define C5_VOLUME_MAX_DIM 65535u
#define C5_VOLUME_MAX_VOXELS ((size_t)1 << 44)

/* Overflow-safe a*b: 0, or -1 when the product does not fit a size_t. */
int c5_mul_size(size_t a, size_t b, size_t *r);
/* Multiplies dims with overflow and limit checks: 0 and the product in *count, or -1. */
int c5_dims_product(const size_t dims[3], size_t *count);
/* Opens a file to read, without blocking (a FIFO with no writer would block open()
 * forever), and refuses anything but a regular file: the descriptor and the file's size, or
 * -1 with "WHERE: cannot open: ..." / "WHERE: not a regular file". The size check needs
 * fstat on the very file read, and a directory would otherwise open and fail obscurely. */
int c5_open_regular(const char *path, const char *where, long long *size, c5_err *err);
/* c5_dims_product says only yes or no; this re-derives why: "PATH: dims AxBxC: ...", -1. */
int c5_dims_fail(const char *path, const size_t dims[3], c5_err *err);

#endif
