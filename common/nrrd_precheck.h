/* The guard in front of Teem's NRRD reader: every Teem call on a user's file goes through
 * c5_nrrd_precheck first. Teem (Debian's 1.12.0~20160122) crashes, over-reads, leaks, blocks
 * or allocates gigabytes on some inputs (docs/nrrd-teem.md); this reads the header and the
 * data's size itself, without Teem, and refuses what Teem must not see:
 *   - a first line other than NRRD0001..NRRD0005, a byte other than printable ASCII or tab
 *     (a NUL among them), a header line longer than C5_NRRD_LINE_MAX, a header longer than
 *     C5_NRRD_HEADER_MAX, a last line without a line end;
 *   - what cube5 does not load anyway: an encoding other than raw or gzip, a type other than
 *     uint8/uint16, a dimension other than 3, sizes beyond c5_dims_product's limits; a type,
 *     dimension or sizes line it cannot read; a field that fixes the data's layout twice;
 *   - more than one detached data file (LIST, SKIPLIST, a %d pattern), "-" (stdin), an
 *     empty name; a header or data file that is not a regular file (a FIFO, /dev/zero);
 *   - data of another size than the header declares: raw data must be exactly
 *     byte skip + sizes x type bytes after the line skip (with byte skip -1, at least the
 *     data); gzip data must be exactly one gzip member that inflates to exactly that many
 *     bytes, with nothing after it (checked with zlib, stopping at the first byte too many).
 * Only then may Teem read the file. */
#ifndef C5_NRRD_PRECHECK_H
#define C5_NRRD_PRECHECK_H

#include <stddef.h>

#include "err.h"
#include "voxel.h"

/* Teem formats some messages, a header line included, into a 1025-byte stack buffer
 * (biff's _HACK_STRLEN, with vsprintf); 400 leaves room for two copies of a line and
 * Teem's own words. The header limit keeps a huge "header" from being read at all. */
#define C5_NRRD_LINE_MAX 400
#define C5_NRRD_HEADER_MAX (64 * 1024)

typedef enum { C5_NRRD_RAW = 1, C5_NRRD_GZIP = 2 } c5_nrrd_encoding;

/* What the precheck read from the header; the loader compares Teem's reading with it. */
typedef struct {
    size_t dims[3];
    c5_voxel_type type;
    size_t data_bytes;              /* dims x bytes of the type */
    c5_nrrd_encoding encoding;
    long line_skip, byte_skip;
    long long data_offset;          /* after the whole precheck: raw, the first voxel's byte in
                                       the data file; gzip, the gzip member's first byte */
    int detached;                   /* the data is in data_path, not after the header */
    char data_path[4096];           /* detached: the data file, resolved like Teem does
                                       (relative names against the header's folder) */
} c5_nrrd_header;

/* 0 when Teem may read `path` (info, when not NULL, says what the header declares), else
 * -1 with "PATH: ..." in err. Reads the header and stats (for gzip: inflates) the data;
 * allocates nothing in proportion to what the header claims. */
int c5_nrrd_precheck_info(const char *path, c5_nrrd_header *info, c5_err *err);
int c5_nrrd_precheck(const char *path, c5_err *err);
/* The whole precheck; for gzip data, the voxels (the inflated stream after its byte skip)
 * are also written to out_fd as the check inflates them: one pass, never whole in memory. */
int c5_nrrd_precheck_inflate(const char *path, c5_nrrd_header *info, int out_fd, c5_err *err);
/* The header part alone (every header rule, nothing of the data: a gzip member is not
 * inflated, a detached data file not opened), for what needs only the declared sizes and
 * the data file's name; the load runs the whole precheck. */
int c5_nrrd_header_info(const char *path, c5_nrrd_header *info, c5_err *err);

/* The loader's message when Teem reads a prechecked header otherwise than the precheck did
 * (never seen; the fuzz harness treats it as a finding). */
#define C5_NRRD_DISAGREE "Teem read the header otherwise than cube5's check did: not loaded"

#endif
