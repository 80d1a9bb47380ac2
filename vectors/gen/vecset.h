/* A vector set: the files of `cube5 vectors` and their manifest (docs/vectors.md).
 *
 * A block's vectors go into one file per source ("directed", or a scene's name):
 * BLOCK.SOURCE.hex, one vector per line, the block's fields in order, each as exactly
 * ceil(width / 4) lowercase hex digits (two's complement, masked to the width, for signed
 * fields), separated by one space, every line ending in '\n'. Nothing else: no header, no
 * comment, so a VHDL testbench reads it with textio's hread field by field. What the columns
 * mean, the block's configuration and the file's CRC-32 are in manifest.json.
 *
 * A block may also write memory images beside its vectors (a table it is configured with,
 * a RAM after its trace): the same format, declared in the manifest as that file's
 * "images". */
#ifndef C5_VECSET_H
#define C5_VECSET_H

#include <jansson.h>
#include <stdint.h>
#include <stdio.h>

#include "err.h"
#include "vblock.h"

#define C5_VSET_FORMAT "cube5-vectors 1" /* manifest.json's "format" */

/* One open file of the set. */
typedef struct c5_vfile c5_vfile;

typedef struct {
    char dir[4096];
    uint64_t seed;
    long count;         /* vectors per (block, source): directed cases and scene taps */
    json_t *files;      /* manifest entries, in the order the files were closed */
    c5_err *err;
    int failed;         /* an I/O error happened; the first message is in *err */
    int vcd;            /* 1: each vector file gets its waveform, BLOCK.SOURCE.vcd (vcd.h) */
} c5_vset;

/* Starts a set writing into dir: created if missing; an earlier set in it is removed (its
 * listed files and manifest, nothing else); a non-empty dir without a set is refused. */
int c5_vset_init(c5_vset *s, const char *dir, uint64_t seed, long count, c5_err *err);
/* Writes manifest.json (the set's parameters and every file's entry) and frees the set.
 * 0, or -1 when anything failed. */
int c5_vset_finish(c5_vset *s, json_t *params);
/* Frees without writing the manifest. */
void c5_vset_abort(c5_vset *s);

/* Opens BLOCK.SOURCE.hex (image NULL: the block's vectors, and with s->vcd their waveform
 * BLOCK.SOURCE.vcd, the manifest entry's "waveform") or BLOCK.SOURCE.IMAGE.hex (a
 * memory image of the block, whose "fields" are one entry's). source: "directed" or the
 * scene's name; scene: the scene's name, NULL for directed vectors. NULL on an error
 * (reported through the set). */
c5_vfile *c5_vfile_open(c5_vset *s, const c5_vblock *b, const char *source, const char *scene, const char *image);
/* The next field of the current vector: a value of at most 64 bits (two's complement for a
 * signed format; one its width cannot carry fails the set, naming file, line and field), or
 * a wide one from little-endian bytes (byte 0 holds bits 7..0). */
void c5_vfile_u(c5_vfile *f, uint64_t v);
void c5_vfile_s(c5_vfile *f, int64_t v);
void c5_vfile_bytes(c5_vfile *f, const uint8_t *le);
/* Ends the vector (asserts that every field was written). */
void c5_vfile_end(c5_vfile *f);
/* Vectors written so far. */
long c5_vfile_count(const c5_vfile *f);
/* A manifest member of the file's entry (e.g. "config"); the reference is stolen. */
void c5_vfile_set(c5_vfile *f, const char *key, json_t *value);
/* Closes the file and adds its manifest entry. */
void c5_vfile_close(c5_vfile *f);

#endif
