/* common/metrics.c against values worked out here from the definitions in metrics.h. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "harness.h"
#include "metrics.h"

/* A w x h image with every channel value v. */
static int flat(c5_image *img, int w, int h, float v)
{
    c5_err err;
    if (c5_image_alloc(img, w, h, &err) != 0)
        return -1;
    for (int i = 0; i < w * h * 3; i++)
        img->rgb[i] = v;
    return 0;
}

static float *at(c5_image *img, int x, int y, int c)
{
    return &img->rgb[3 * (y * img->w + x) + c];
}

TEST(metrics_identical_images)
{
    c5_image a, b;
    c5_image_diff d;
    c5_err err;
    CHECK(flat(&a, 4, 3, 0.3f) == 0 && flat(&b, 4, 3, 0.3f) == 0);
    *at(&a, 1, 2, 0) = *at(&b, 1, 2, 0) = 7.5f; /* out of display range, still equal */
    CHECK_INT(c5_image_compare(&a, &b, &d, &err), 0);
    CHECK(d.rmse == 0.0 && d.max_abs_err == 0.0);
    CHECK(d.psnr_db == C5_PSNR_CAP);
    for (int c = 0; c < 3; c++)
        CHECK(d.rmse_ch[c] == 0.0 && d.max_abs_ch[c] == 0.0 && d.psnr_ch[c] == C5_PSNR_CAP);
    CHECK_INT(d.hist[0], 4 * 3 * 3);
    for (int i = 1; i < C5_METRIC_BINS; i++)
        CHECK_INT(d.hist[i], 0);
    CHECK_INT(d.values, 36);
    CHECK_INT(d.differing, 0);
    c5_image_free(&a);
    c5_image_free(&b);
}

TEST(metrics_one_value_off)
{
    /* 4x3 image, 36 channel values; one of them (pixel (2,1), green) off by delta = 2^-6,
     * exact in float. rmse = sqrt(delta^2 / 36) = delta / 6; green's rmse over its 12 values
     * = delta / sqrt(12); PSNR = 20 log10(1 / rmse). In steps, delta * 255 = 3.98..., which
     * lies in (2, 4]: bin 5. */
    const double delta = 1.0 / 64.0;
    c5_image ref, test;
    c5_image_diff d;
    c5_err err;
    CHECK(flat(&ref, 4, 3, 0.5f) == 0 && flat(&test, 4, 3, 0.5f) == 0);
    *at(&test, 2, 1, 1) = (float)(0.5 + delta);
    CHECK_INT(c5_image_compare(&ref, &test, &d, &err), 0);
    CHECK_NEAR(d.rmse, delta / 6.0, 1e-15);
    CHECK_NEAR(d.psnr_db, 20.0 * log10(6.0 / delta), 1e-9);
    CHECK(d.max_abs_err == delta);
    CHECK(d.rmse_ch[0] == 0.0 && d.rmse_ch[2] == 0.0);
    CHECK_NEAR(d.rmse_ch[1], delta / sqrt(12.0), 1e-15);
    CHECK_NEAR(d.psnr_ch[1], 20.0 * log10(sqrt(12.0) / delta), 1e-9);
    CHECK(d.psnr_ch[0] == C5_PSNR_CAP && d.psnr_ch[2] == C5_PSNR_CAP);
    CHECK(d.max_abs_ch[0] == 0.0 && d.max_abs_ch[1] == delta && d.max_abs_ch[2] == 0.0);
    CHECK(delta * 255.0 > 2.0 && delta * 255.0 <= 4.0);
    CHECK_INT(d.hist[0], 35);
    CHECK_INT(d.hist[5], 1);
    CHECK_INT(d.differing, 1);
    /* The sign does not matter: the same error downwards gives the same numbers. */
    *at(&test, 2, 1, 1) = (float)(0.5 - delta);
    c5_image_diff d2;
    CHECK_INT(c5_image_compare(&ref, &test, &d2, &err), 0);
    CHECK(d2.rmse == d.rmse && d2.max_abs_err == d.max_abs_err && d2.hist[5] == 1);
    c5_image_free(&ref);
    c5_image_free(&test);
}

TEST(metrics_per_channel)
{
    /* 2x2 image at 0.25. Red is +1/8 on every pixel, green -1/16 on one pixel, blue exact.
     * rmse_ch = {1/8, sqrt((1/16)^2 / 4) = 1/32, 0}; overall over 12 values
     * sqrt((4 (1/8)^2 + (1/16)^2) / 12). Red: 1/8 * 255 = 31.9 steps, beyond 16: bin 8;
     * green: 15.9 steps, in (8, 16]: bin 7. */
    c5_image ref, test;
    c5_image_diff d;
    c5_err err;
    CHECK(flat(&ref, 2, 2, 0.25f) == 0 && flat(&test, 2, 2, 0.25f) == 0);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 2; x++)
            *at(&test, x, y, 0) = 0.375f;
    *at(&test, 1, 0, 1) = 0.1875f;
    CHECK_INT(c5_image_compare(&ref, &test, &d, &err), 0);
    CHECK_NEAR(d.rmse_ch[0], 1.0 / 8, 1e-15);
    CHECK_NEAR(d.rmse_ch[1], 1.0 / 32, 1e-15);
    CHECK(d.rmse_ch[2] == 0.0);
    double all = sqrt((4.0 / 64 + 1.0 / 256) / 12.0);
    CHECK_NEAR(d.rmse, all, 1e-15);
    CHECK_NEAR(d.psnr_db, -20.0 * log10(all), 1e-9);
    CHECK_NEAR(d.psnr_ch[0], 20.0 * log10(8.0), 1e-9);
    CHECK_NEAR(d.psnr_ch[1], 20.0 * log10(32.0), 1e-9);
    CHECK(d.psnr_ch[2] == C5_PSNR_CAP);
    CHECK(d.max_abs_ch[0] == 0.125 && d.max_abs_ch[1] == 0.0625 && d.max_abs_ch[2] == 0.0);
    CHECK(d.max_abs_err == 0.125);
    CHECK_INT(d.hist[8], 4);
    CHECK_INT(d.hist[7], 1);
    CHECK_INT(d.hist[0], 7);
    c5_image_free(&ref);
    c5_image_free(&test);
}

TEST(metrics_bin_edges_upper_inclusive)
{
    /* Bin 0 is exact zero; an error exactly on an edge belongs to the bin below it, the
     * next double above the edge to the bin above. */
    CHECK_INT(c5_metric_bin(0.0), 0);
    CHECK_INT(c5_metric_bin(DBL_TRUE_MIN), 1);
    for (int i = 1; i < C5_METRIC_BINS - 1; i++) {
        double e = c5_metric_bin_edge(i);
        CHECK_MSG(c5_metric_bin(e) == i, "edge %g in bin %d, expected %d", e, c5_metric_bin(e), i);
        CHECK_MSG(c5_metric_bin(nextafter(e, INFINITY)) == i + 1, "just above %g in bin %d", e,
                  c5_metric_bin(nextafter(e, INFINITY)));
        CHECK(e > c5_metric_bin_edge(i - 1));
    }
    CHECK(c5_metric_bin_edge(1) == 0.25 && c5_metric_bin_edge(C5_METRIC_BINS - 2) == 16.0);
    CHECK_INT(c5_metric_bin(1e30), C5_METRIC_BINS - 1);
    CHECK_INT(c5_metric_bin(INFINITY), C5_METRIC_BINS - 1);
    CHECK(!strcmp(c5_metric_bin_label(0), "0"));
    CHECK(!strcmp(c5_metric_bin_label(1), "(0, 0.25]"));
    CHECK(!strcmp(c5_metric_bin_label(C5_METRIC_BINS - 1), "> 16"));
}

TEST(metrics_histogram_around_one_step)
{
    /* One 8-bit step is 1/255, not a float; the largest float t with t * 255 <= 1 counts in
     * (0.5, 1], the next float up in (1, 2]. */
    float t = (float)(1.0 / 255.0);
    while ((double)t * 255.0 > 1.0)
        t = nextafterf(t, 0.0f);
    while ((double)nextafterf(t, 1.0f) * 255.0 <= 1.0)
        t = nextafterf(t, 1.0f);
    c5_image ref, test;
    c5_image_diff d;
    c5_err err;
    CHECK(flat(&ref, 2, 1, 0.0f) == 0 && flat(&test, 2, 1, 0.0f) == 0);
    *at(&test, 0, 0, 0) = t;
    *at(&test, 1, 0, 2) = nextafterf(t, 1.0f);
    CHECK_INT(c5_image_compare(&ref, &test, &d, &err), 0);
    CHECK_INT(d.hist[0], 4);
    CHECK_INT(d.hist[3], 1);
    CHECK_INT(d.hist[4], 1);
    c5_image_free(&ref);
    c5_image_free(&test);
}

TEST(metrics_refuses_size_mismatch_and_nan)
{
    c5_image a, b, c;
    c5_image_diff d;
    c5_err err;
    CHECK(flat(&a, 4, 3, 0.5f) == 0 && flat(&b, 3, 4, 0.5f) == 0 && flat(&c, 4, 3, 0.5f) == 0);
    CHECK_INT(c5_image_compare(&a, &b, &d, &err), -1);
    CHECK_HAS(err.msg, "sizes differ");
    CHECK_HAS(err.msg, "4x3");
    c5_image out;
    CHECK_INT(c5_image_diff_image(&a, &b, 16.0, &out, &err), -1);
    CHECK(out.rgb == NULL);
    *at(&c, 3, 2, 1) = NAN;
    CHECK_INT(c5_image_compare(&a, &c, &d, &err), -1);
    CHECK_HAS(err.msg, "test image has NaN at pixel (3, 2) channel 1");
    CHECK_INT(c5_image_compare(&c, &a, &d, &err), -1);
    CHECK_HAS(err.msg, "reference image has NaN");
    *at(&c, 3, 2, 1) = INFINITY;
    CHECK_INT(c5_image_compare(&a, &c, &d, &err), -1);
    CHECK_HAS(err.msg, "infinity");
    CHECK_INT(c5_image_diff_image(&a, &c, 16.0, &out, &err), -1);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_image_free(&c);
}

TEST(metrics_diff_image)
{
    c5_image ref, test, out;
    c5_err err;
    CHECK(flat(&ref, 3, 2, 0.5f) == 0 && flat(&test, 3, 2, 0.5f) == 0);
    *at(&test, 2, 1, 0) = 0.5f + 1.0f / 64;
    *at(&test, 0, 0, 2) = 0.5f - 1.0f / 128;
    CHECK_INT(c5_image_diff_image(&ref, &test, C5_DIFF_GAIN, &out, &err), 0);
    CHECK_INT(out.w, 3);
    CHECK_INT(out.h, 2);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++)
            for (int c = 0; c < 3; c++) {
                double want = fabs((double)*at(&test, x, y, c) - (double)*at(&ref, x, y, c)) * C5_DIFF_GAIN;
                CHECK_MSG(*at(&out, x, y, c) == (float)want, "(%d,%d,%d): %g, expected %g", x, y, c,
                          (double)*at(&out, x, y, c), want);
            }
    CHECK(*at(&out, 2, 1, 0) == 0.25f && *at(&out, 0, 0, 2) == 0.125f);
    c5_image_free(&out);
    CHECK_INT(c5_image_diff_image(&ref, &test, 0.0, &out, &err), -1);
    CHECK_HAS(err.msg, "gain");
    CHECK_INT(c5_image_diff_image(&ref, &test, NAN, &out, &err), -1);
    CHECK_INT(c5_image_diff_image(&ref, &test, -2.0, &out, &err), -1);
    c5_image_free(&ref);
    c5_image_free(&test);
}
