/* A block as its vector files and waveforms describe it: its fields in column order. */
#ifndef C5_VBLOCK_H
#define C5_VBLOCK_H

typedef struct {
    const char *name;
    unsigned width;     /* bits, 1..256 */
    int out;            /* 1: an output of the block (expected), 0: an input */
    const char *format; /* "uint", "sint", "UQi.f", "SQi.f", "bits" */
} c5_vfield;

typedef struct {
    const char *name;   /* block name: file prefix and manifest "block" */
    const char *doc;    /* one sentence for the manifest */
    const c5_vfield *fields;
    int n_fields;
} c5_vblock;

#endif
