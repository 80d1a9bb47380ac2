/* One volume of a scene as a source of 8-bit voxels, read box by box (docs/out-of-core.md):
 * a raw or NRRD file read at its data's offset with positioned reads (pread), uint16 mapped
 * through its window on the way, or a generator evaluated per voxel. No source holds its
 * voxels in memory; a read costs the box (and, for files, a bounded scratch buffer). */
#ifndef C5_VOXSRC_H
#define C5_VOXSRC_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "scene.h"

typedef struct c5_voxsrc c5_voxsrc;

/* Opens the volume d describes as far as its dims and type (c5_volume_probe: no data read,
 * so that the grid's limits come before any volume work); a generator's set-up. 0, or -1
 * with "PATH: ..." in err. */
int c5_voxsrc_open(const c5_volume_desc *d, c5_voxsrc **out, c5_err *err);
/* Then, before the first read: a file with every check of c5_volume_load (c5_volume_open:
 * the NRRD precheck, gzip inflated, Teem on the header), its own spacing, and for uint16
 * without a window the file's min and max (one streaming pass in chunks). */
int c5_voxsrc_prepare(c5_voxsrc *s, c5_err *err);
void c5_voxsrc_close(c5_voxsrc *s);

const size_t *c5_voxsrc_dims(const c5_voxsrc *s);
int c5_voxsrc_is_generator(const c5_voxsrc *s);
/* The file's own spacing, all 0 when it states none (raw files, generators); known after
 * c5_voxsrc_prepare. */
const double *c5_voxsrc_spacing(const c5_voxsrc *s);
/* "generator NAME XxYxZ" or "file NAME XxYxZ TYPE[ window [lo, hi]]" */
const char *c5_voxsrc_label(const c5_voxsrc *s);

/* Voxels [lo, hi) of the source (hi <= dims, lo < hi) as 8-bit values: voxel (x, y, z) at
 * out[(z - lo[2]) sz + (y - lo[1]) sy + x - lo[0]]. The bits depend on the voxel alone, never
 * on the box. Thread-safe. 0, or -1 with "PATH: read failed: ..." in err. */
int c5_voxsrc_read(const c5_voxsrc *s, const size_t lo[3], const size_t hi[3], uint8_t *out, size_t sy, size_t sz,
                   c5_err *err);

/* A source's identity for caches of what is derived from its voxels, in a string: a file's
 * device, inode, size, modification time to the nanosecond, data offset and type, window
 * (uint16) and dims; a generator's name, dims and parameters and when the generators were
 * compiled. 0, or -1: a file not open, or modified less than C5_IDENTITY_AGE_S seconds ago
 * (rewritten within one tick of the file system's clock it would keep its identity with
 * other voxels; a cache made when it is older cannot be taken for a later rewrite's, whose
 * time is later than the cache's). After c5_voxsrc_prepare. */
#define C5_IDENTITY_AGE_S 2
int c5_voxsrc_identity(const c5_voxsrc *s, char *buf, size_t n);
/* A uint8 file's voxels mapped read-only (mmap): *data the first voxel, *base and *len what
 * to munmap. 0, or -1 (a generator, uint16, or the system refused: the caller reads instead).
 * A file cut short while mapped ends the run with the message of a failed read. */
int c5_voxsrc_map(const c5_voxsrc *s, void **base, size_t *len, const uint8_t **data);
/* A file just mapped (by c5_voxsrc_map, or a cache file): if it is cut short while mapped,
 * the fault ends the run with "cube5: error: PATH: read failed: ...", exit 2, naming the
 * file mapped last. */
void c5_map_guard(const char *path);

#endif
