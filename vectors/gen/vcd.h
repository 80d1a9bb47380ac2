/* Waveforms of a block's vectors (docs/vectors.md, "Waveforms"): the VCD that
 * `cube5 vectors --vcd` writes beside each vector file BLOCK.SOURCE.hex, as BLOCK.SOURCE.vcd,
 * and the waveform of a frame's cycle-level parts that `cube5 render --vcd` writes
 * (frame_vcd.h), one scope a part.
 *
 * One scope named after the block, one signal per field of the block (the manifest's names,
 * which are the VHDL entity's ports where the block has VHDL), plus `clk` and `rst`, on the
 * clock of the testbenches in tb/ (tb_ray_queue.vhd): a 10 ns period, one reset cycle
 * (rst high through the first rising edge at 5 ns), then vector n's values from
 * 10 (n + 1) ns, sampled at the rising edge 5 ns later. GHDL's `--vcd` of the testbench on
 * the same vector file shows the same values at every rising edge, so the two load side by
 * side in GTKWave. Fields are unknown (x) before the first vector. With several scopes every
 * scope declares the same `clk` and `rst` (one VCD identifier each). */
#ifndef C5_VCD_H
#define C5_VCD_H

#include "atomic_file.h"
#include "err.h"
#include "vblock.h"

#define C5_VCD_HALF_NS 5 /* half the clock period: the board's 100 MHz */
#define C5_VCD_MAX_SCOPES 4

typedef struct c5_vcd c5_vcd;

/* Creates path and writes the header; NULL with errno set on an I/O error. */
c5_vcd *c5_vcd_open(const char *path, const c5_vblock *b);
/* One vector: `line` as written to the .hex file (the fields' hex digits separated by one
 * space, '\n' optional). Writes the values that changed. 0, or -1 on an I/O error. */
int c5_vcd_vector(c5_vcd *v, const char *line);
/* The last cycle's rising and falling edges, then puts the file in place whole
 * (atomic_file.h); 0, or -1 naming the file and the reason. Frees v. */
int c5_vcd_close(c5_vcd *v, c5_err *err);
/* Drops the waveform: the file is as it was. Frees v. */
void c5_vcd_abort(c5_vcd *v);

/* Several scopes (blocks[0..n-1], named after the blocks), for a caller that draws the clock
 * itself. The time unit is 1 fs when `fs` (GHDL's own unit; room for events between two
 * clock edges), else 1 ns. `version` goes into $version, `comment` (or NULL) into a $comment
 * of the header. With `exclusive`, an existing path is refused (NULL, errno EEXIST). The
 * header ends with the reset edge (time 5 ns) written. */
c5_vcd *c5_vcd_open_scopes(const char *path, const c5_vblock *const *blocks, int n, const char *version,
                           const char *comment, int fs, int exclusive);
/* Time units a ns (1, or 1000000 with fs). */
long long c5_vcd_unit(const c5_vcd *v);
/* Moves on to time t (in the file's units); a time before the last is an error (-1). */
int c5_vcd_at(c5_vcd *v, long long t);
/* The clock's and the reset's level at the current time. */
void c5_vcd_clk(c5_vcd *v, int level);
void c5_vcd_rst(c5_vcd *v, int level);
/* The values of scope k's fields at the current time from a line as c5_vcd_vector's; a
 * field of 'x' digits is unknown. Writes the values that changed. 0, or -1 on an I/O error. */
int c5_vcd_values(c5_vcd *v, int k, const char *line);

#endif
