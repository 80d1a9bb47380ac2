/* Image comparison; every definition is in metrics.h and docs/compare.md. */
#include "metrics.h"

#include <math.h>
#include <string.h>

/* Upper edges of bins 1..8 in 8-bit steps (1/255 of full scale). Bin 0 is exact equality;
 * the bins then double from a quarter step, because the interesting question is first "below
 * one PNG level?" (bins 1-3) and then "how many levels?" (bins 4-8). */
static const struct {
    double edge;
    const char *label;
} bins[C5_METRIC_BINS] = {
    {0.0, "0"},          {0.25, "(0, 0.25]"}, {0.5, "(0.25, 0.5]"}, {1.0, "(0.5, 1]"}, {2.0, "(1, 2]"},
    {4.0, "(2, 4]"},     {8.0, "(4, 8]"},     {16.0, "(8, 16]"},    {INFINITY, "> 16"},
};

int c5_metric_bin(double steps)
{
    if (steps <= 0.0)
        return 0;
    int i = 1;
    while (i < C5_METRIC_BINS - 1 && steps > bins[i].edge)
        i++;
    return i;
}

const char *c5_metric_bin_label(int i)
{
    return i >= 0 && i < C5_METRIC_BINS ? bins[i].label : "?";
}

double c5_metric_bin_edge(int i)
{
    return i >= 0 && i < C5_METRIC_BINS ? bins[i].edge : NAN;
}

double c5_psnr_db(double rmse)
{
    if (rmse <= 0.0)
        return C5_PSNR_CAP;
    double db = 20.0 * log10(1.0 / rmse); /* peak 1.0: the display range [0,1] */
    return db > C5_PSNR_CAP ? C5_PSNR_CAP : db;
}

/* Both images present, the same size and finite everywhere. */
static int check_pair(const c5_image *ref, const c5_image *test, c5_err *err)
{
    if (!ref || !test || !ref->rgb || !test->rgb)
        return c5_fail(err, "compare: internal error: missing image");
    if (ref->w != test->w || ref->h != test->h)
        return c5_fail(err, "compare: image sizes differ: reference %dx%d, test %dx%d", ref->w, ref->h, test->w,
                       test->h);
    size_t n = (size_t)ref->w * (size_t)ref->h * 3;
    for (int k = 0; k < 2; k++) {
        const float *v = k ? test->rgb : ref->rgb;
        for (size_t i = 0; i < n; i++)
            if (!isfinite(v[i])) {
                size_t px = i / 3;
                return c5_fail(err, "compare: %s image has %s at pixel (%zu, %zu) channel %zu",
                               k ? "test" : "reference", isnan(v[i]) ? "NaN" : "an infinity", px % (size_t)ref->w,
                               px / (size_t)ref->w, i % 3);
            }
    }
    return 0;
}

int c5_image_compare(const c5_image *ref, const c5_image *test, c5_image_diff *out, c5_err *err)
{
    if (!out)
        return c5_fail(err, "compare: internal error: no result");
    memset(out, 0, sizeof *out);
    if (check_pair(ref, test, err) != 0)
        return -1;
    size_t px = (size_t)ref->w * (size_t)ref->h;
    double sq[3] = {0, 0, 0};
    for (size_t i = 0; i < px; i++)
        for (int c = 0; c < 3; c++) {
            double e = (double)test->rgb[3 * i + c] - (double)ref->rgb[3 * i + c];
            double a = fabs(e);
            sq[c] += e * e;
            if (a > out->max_abs_ch[c])
                out->max_abs_ch[c] = a;
            out->hist[c5_metric_bin(a * 255.0)]++;
            out->differing += a != 0.0;
        }
    double total = 0.0;
    for (int c = 0; c < 3; c++) {
        total += sq[c];
        out->rmse_ch[c] = sqrt(sq[c] / (double)px);
        out->psnr_ch[c] = c5_psnr_db(out->rmse_ch[c]);
        if (out->max_abs_ch[c] > out->max_abs_err)
            out->max_abs_err = out->max_abs_ch[c];
    }
    out->rmse = sqrt(total / (3.0 * (double)px));
    out->psnr_db = c5_psnr_db(out->rmse);
    out->values = 3 * (uint64_t)px;
    out->w = ref->w;
    out->h = ref->h;
    return 0;
}

int c5_image_diff_image(const c5_image *ref, const c5_image *test, double gain, c5_image *out, c5_err *err)
{
    if (!out)
        return c5_fail(err, "compare: internal error: no output image");
    memset(out, 0, sizeof *out);
    if (!isfinite(gain) || gain <= 0.0)
        return c5_fail(err, "compare: difference gain must be finite and > 0, got %g", gain);
    if (check_pair(ref, test, err) != 0 || c5_image_alloc(out, ref->w, ref->h, err) != 0)
        return -1;
    size_t n = (size_t)ref->w * (size_t)ref->h * 3;
    for (size_t i = 0; i < n; i++)
        out->rgb[i] = (float)(fabs((double)test->rgb[i] - (double)ref->rgb[i]) * gain);
    return 0;
}
