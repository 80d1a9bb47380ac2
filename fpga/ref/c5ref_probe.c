/* The rounding and saturation probe of the model (rtl_model/proc/round_probe.h), read through the
 * library: libc5ref.so is built with -DC5_ROUND_PROBE, so every rounder and clamp of the
 * blocks it runs records its event at its site. scripts/vectors_coverage.py replays each
 * vector of a set through the block's reference and reads the events here. */
#include <stdint.h>
#include <string.h>

#include "round_probe.h"

#ifndef C5_ROUND_PROBE
#error "fpga/ref is built with -DC5_ROUND_PROBE (Makefile, REF_SO)"
#endif

int c5_round_site;
unsigned c5_round_seen[C5_RS_COUNT];

int32_t c5ref_probe_sites(void);
const char *c5ref_probe_site_name(int32_t i);
void c5ref_probe_reset(void);
int32_t c5ref_probe_seen(int32_t i);

#define C5_RS_NAME(id, name) name,
static const char *const site_names[C5_RS_COUNT] = {C5_ROUND_SITES(C5_RS_NAME)};

int32_t c5ref_probe_sites(void) { return C5_RS_COUNT; }

/* "block.site" of site i, NULL outside 0 .. c5ref_probe_sites() - 1. */
const char *c5ref_probe_site_name(int32_t i) { return i >= 0 && i < C5_RS_COUNT ? site_names[i] : NULL; }

/* Forgets the events; the next rounding without a site counts under "none". */
void c5ref_probe_reset(void)
{
    memset(c5_round_seen, 0, sizeof c5_round_seen);
    c5_round_site = C5_RS_NONE;
}

/* The events (C5_EV_* bits) site i met since the last reset. */
int32_t c5ref_probe_seen(int32_t i) { return i >= 0 && i < C5_RS_COUNT ? (int32_t)c5_round_seen[i] : 0; }
