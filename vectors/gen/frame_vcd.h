/* The waveform of a frame's cycle-level parts (`cube5 render --vcd FILE`, docs/vectors.md,
 * "Waveforms of a frame"): taps on the board model (rtl_model/proc/taps.h) that write one VCD
 * (vcd.h) with two scopes on the testbenches' 10 ns clock:
 *
 *   ray_queue  the board's eDRAM sorter, whose entries are the active cell's rays (the board
 *              has one sorter; it serves each loaded cell in turn), one cycle a clock as
 *              the model steps it, from reset: the ports of fpga/rtl/ray_queue.vhd, the
 *              fields of the ray_queue vectors. Cycle n is at the same time as vector n of
 *              ray_queue.SCENE.vcd (`cube5 vectors --vcd`) and of GHDL's tb_ray_queue.
 *   ray_bus    the packets crossing the ray bus between the processor and the DSP: `valid`,
 *              `to_dsp` (1: processor -> DSP, before the DSP's Cell Tree tag; 0: the active
 *              cell's SDRAM queue streaming into the sorter) and the packet codec's fields
 *              (spec/layouts.toml) with the whole 256-bit `packet`, as the packet vectors.
 *
 * A packet into the sorter sits in the cycle that inserts it. The model does not clock the
 * sorter while the processor traces the ray it popped, so the packets that ray sends to the
 * DSP (and the set-up's eye rays, before the first cycle) fall between two edges: they are
 * drawn one after another, evenly spaced in the 5 ns after the rising edge of the pop, each
 * with a `valid` pulse; hence the 1 fs time unit (GHDL's own). Times are the cycle's, so a
 * window (from, cycles) lines up with a waveform of the whole frame. */
#ifndef C5_FRAME_VCD_H
#define C5_FRAME_VCD_H

#include <stdint.h>

#include "err.h"
#include "taps.h"

typedef struct c5_frame_vcd c5_frame_vcd;

typedef struct {
    uint64_t cycles;        /* the sorter's cycles in the frame */
    uint64_t to_dsp, from_dsp; /* packets over the ray bus in the frame, each way */
    uint64_t written;       /* sorter cycles in the file */
    int cut;                /* the frame went on after the window */
} c5_frame_vcd_stats;

/* Creates `path` (an existing file is refused: errno EEXIST) for the sorter's cycles
 * from .. from + cycles - 1 and the bus packets among them (with from 0 also those before
 * the first cycle); `about` goes into the header's comment. NULL with err set. */
c5_frame_vcd *c5_frame_vcd_open(const char *path, uint64_t from, uint64_t cycles, const char *about, c5_err *err);
/* The taps to give the board (c5_board_opts.taps). */
const c5_taps *c5_frame_vcd_taps(c5_frame_vcd *w);
/* Writes what is pending, closes and frees; 0, or -1 with err set on an I/O error. */
int c5_frame_vcd_close(c5_frame_vcd *w, c5_frame_vcd_stats *st, c5_err *err);
/* Drops the waveform of a frame that failed: the file is as it was. Frees w. */
void c5_frame_vcd_abort(c5_frame_vcd *w);

#endif
