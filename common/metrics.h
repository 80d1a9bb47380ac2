/* Image comparison: how far a test image (the board model's) is from a reference (cref's).
 * Definitions, also in docs/compare.md:
 *  - the values compared are the linear frame-buffer floats, before any PNG clamping;
 *  - the error of one channel of one pixel is e = test - ref, computed in double;
 *  - rmse = sqrt(mean of e^2) over every channel of every pixel (3*w*h values); rmse_ch[c]
 *    over channel c only (w*h values);
 *  - psnr = 20 log10(peak / rmse) dB with peak = 1.0, because the display range is [0,1]:
 *    a PNG maps [0,1] to 0..255. rmse == 0 (identical) has no finite PSNR: psnr is then
 *    C5_PSNR_CAP, and any PSNR above the cap is capped too, so that JSON (no infinities)
 *    and text agree; text output prints "inf" when rmse == 0;
 *  - max_abs_err = max |e|; max_abs_ch[c] per channel;
 *  - hist counts every channel value (3*w*h in all) by |e| in 8-bit display steps,
 *    steps = |e| * 255: bin 0 holds exactly 0, bin i > 0 holds (edge[i-1], edge[i]] (upper edge
 *    inclusive), the last bin everything above the last edge. */
#ifndef C5_METRICS_H
#define C5_METRICS_H

#include <stdint.h>

#include "err.h"
#include "image.h"

#define C5_METRIC_BINS 9
/* 200 dB: an rmse of 1e-10 of full scale, far below one float step near 1.0 (1.2e-7,
 * 138 dB), so a capped PSNR means "equal as far as the frame buffer can say". */
#define C5_PSNR_CAP 200.0
/* Default gain of the difference image: one 8-bit step of error shows as 16 steps of grey,
 * and an error of 1/16 of full scale or more is white. */
#define C5_DIFF_GAIN 16.0

typedef struct {
    double psnr_db, rmse, max_abs_err;
    double rmse_ch[3], max_abs_ch[3], psnr_ch[3];
    uint64_t hist[C5_METRIC_BINS];
    uint64_t values;        /* channel values compared: 3*w*h (the sum of hist) */
    uint64_t differing;     /* channel values with e != 0 */
    int w, h;
} c5_image_diff;

/* Fills out. Errors: a missing image, different sizes, a NaN or infinity in either image. */
int c5_image_compare(const c5_image *ref, const c5_image *test, c5_image_diff *out, c5_err *err);

/* The histogram bin of an error of `steps` 8-bit steps (>= 0), by the rule above. */
int c5_metric_bin(double steps);
/* Label of bin i, e.g. "0", "(0, 0.25]", "> 16"; upper edge of bin i in steps (0 for bin 0,
 * INFINITY for the last). */
const char *c5_metric_bin_label(int i);
double c5_metric_bin_edge(int i);

/* PSNR in dB of an rmse by the rule above (capped at C5_PSNR_CAP). */
double c5_psnr_db(double rmse);

/* out (allocated here) = |test - ref| * gain per channel, a viewable difference image (a PNG
 * clamps it to [0,1]). gain must be finite and > 0. Same errors as c5_image_compare. */
int c5_image_diff_image(const c5_image *ref, const c5_image *test, double gain, c5_image *out, c5_err *err);

#endif
