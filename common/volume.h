/* Volumes: loading raw and NRRD files, and the 8-bit super volume the board renders.
 *
 * Layout everywhere: x fastest, then y, then z (C array [z][y][x]); voxel values in host
 * byte order once loaded. A loaded file keeps its own type (uint8 or uint16); the scene
 * turns it into the 8-bit grid that both renderers sample (see docs/rendering-spec.md). */
#ifndef C5_VOLUME_H
#define C5_VOLUME_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "voxel.h"


typedef struct {
    size_t dims[3];     /* x, y, z */
    c5_voxel_type type;
    void *data;         /* dims[0]*dims[1]*dims[2] voxels of `type`, host byte order */
    double spacing[3];  /* from a NRRD header when it gives one, else 0 (unknown) */
} c5_volume;

/* How to read a raw file. dims all 0 and type NONE: take both from an Open SciVis name
 * (NAME_XxYxZ_uint8.raw); otherwise both must be given. uint16 raw is little-endian
 * unless big_endian is set. */
typedef struct {
    size_t dims[3];
    c5_voxel_type type;
    int big_endian;
} c5_raw_spec;

/* Parses "..._XxYxZ_uint8.raw" / "_uint16.raw" from the file's base name.
 * Returns 0 and fills dims/type, or -1 when the name does not follow the pattern. */
int c5_scivis_name(const char *path, size_t dims[3], c5_voxel_type *type);

int c5_volume_load_raw(const char *path, const c5_raw_spec *spec, c5_volume *out, c5_err *err);
/* NRRD through Teem: attached (.nrrd) and detached (.nhdr) headers, raw and gzip encodings,
 * either endianness; 3-D scalar uchar/ushort only (signed types and others are refused).
 * c5_nrrd_precheck (nrrd_precheck.h) reads the header and sizes the data before Teem runs;
 * spacing[] is the header's spacings (or space directions' lengths), 0 where it gives none. */
int c5_volume_load_nrrd(const char *path, c5_volume *out, c5_err *err);
/* Dispatches on the extension: .nrrd/.nhdr to NRRD, anything else to raw. */
int c5_volume_load(const char *path, const c5_raw_spec *spec, c5_volume *out, c5_err *err);
void c5_volume_free(c5_volume *v);

/* A volume file opened for reads at an offset (common/voxsrc.c reads it box by box): the
 * same checks as c5_volume_load (the NRRD precheck, then Teem on the header alone), no voxel
 * in memory. The voxels are `count` values of `type` from byte `offset` of fd, x fastest, in
 * the file's byte order (big_endian). Raw data is read in place (the raw file, or the NRRD's
 * own or detached data file); gzip NRRD data cannot be read at an offset, so the precheck's
 * one inflating pass writes it to an unlinked temporary file in $TMPDIR (else /tmp), which fd
 * then is (gone when closed). The caller closes fd. */
typedef struct {
    size_t dims[3];
    c5_voxel_type type;
    int big_endian;
    double spacing[3];   /* as c5_volume's */
    int fd;
    long long offset;
} c5_volume_file;
int c5_volume_open(const char *path, const c5_raw_spec *spec, c5_volume_file *out, c5_err *err);
/* The dims and type alone, before any data is read, inflated or handed to Teem: a raw file's
 * checks (they cost a stat), a NRRD's header rules (c5_nrrd_header_info). fd stays -1. */
int c5_volume_probe(const char *path, const c5_raw_spec *spec, c5_volume_file *out, c5_err *err);

size_t c5_volume_count(const c5_volume *v);
/* Voxel value as an unsigned integer, whatever the type. No bounds check. */
unsigned c5_volume_at(const c5_volume *v, size_t i);


#endif
