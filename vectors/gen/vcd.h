/* Waveforms of a block's vectors (docs/vectors.md, "Waveforms"): the VCD that
 * `cube5 vectors --vcd` writes beside each vector file BLOCK.SOURCE.hex, as BLOCK.SOURCE.vcd.
 *
 * One scope named after the block, one signal per field of the block (the manifest's names,
 * which are the VHDL entity's ports where the block has VHDL), plus `clk` and `rst`, on the
 * clock of the testbenches in fpga/tb/ (tb_ray_queue.vhd): a 10 ns period, one reset cycle
 * (rst high through the first rising edge at 5 ns), then vector n's values from
 * 10 (n + 1) ns, sampled at the rising edge 5 ns later. GHDL's `--vcd` of the testbench on
 * the same vector file shows the same values at every rising edge, so the two load side by
 * side in GTKWave. Fields are unknown (x) before the first vector. */
#ifndef C5_VCD_H
#define C5_VCD_H

#include "vecset.h"

#define C5_VCD_HALF_NS 5 /* half the clock period: the board's 100 MHz */

typedef struct c5_vcd c5_vcd;

/* Creates path and writes the header; NULL with errno set on an I/O error. */
c5_vcd *c5_vcd_open(const char *path, const c5_vblock *b);
/* One vector: `line` as written to the .hex file (the fields' hex digits separated by one
 * space, '\n' optional). Writes the values that changed. 0, or -1 on an I/O error. */
int c5_vcd_vector(c5_vcd *v, const char *line);
/* The last cycle's rising and falling edges, then closes; 0, or -1 on an I/O error. Frees v. */
int c5_vcd_close(c5_vcd *v);

#endif
