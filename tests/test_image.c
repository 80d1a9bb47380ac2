/* Unit tests for common/image.c and common/image_oiio.cpp. */
#include "harness.h"
#include "image.h"

#include <dirent.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

/* The documented PNG rule: clamp to [0,1], then floor(v*255 + 0.5) in double precision. */
static int expected8(float v)
{
    double d = v;
    if (d < 0.0)
        d = 0.0;
    if (d > 1.0)
        d = 1.0;
    return (int)floor(d * 255.0 + 0.5);
}

static int file_exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

/* Number of entries in the test's temporary directory (excluding . and ..); if one is given,
 * copies the name of the last entry that is not `except` into other (for messages). */
static int dir_count(char *other, size_t other_size, const char *except)
{
    DIR *d = opendir(c5t_tmpdir());
    if (!d)
        return -1;
    int n = 0;
    if (other_size)
        other[0] = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        n++;
        if (other_size && (!except || strcmp(e->d_name, except) != 0))
            snprintf(other, other_size, "%s", e->d_name);
    }
    closedir(d);
    return n;
}

static int write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t wr = fwrite(data, 1, n, f);
    return (fclose(f) == 0 && wr == n) ? 0 : -1;
}

static void fill_pattern(c5_image *img)
{
    for (int y = 0; y < img->h; y++)
        for (int x = 0; x < img->w; x++)
            for (int c = 0; c < 3; c++)
                img->rgb[3 * (y * img->w + x) + c] = 0.1f * (float)x + 0.01f * (float)y + 0.3f * (float)c;
}

TEST(image_alloc_ok_and_free_zeroes)
{
    c5_err err = {{0}};
    c5_image img;
    CHECK_INT(c5_image_alloc(&img, 3, 2, &err), 0);
    CHECK_INT(img.w, 3);
    CHECK_INT(img.h, 2);
    CHECK(img.rgb != NULL);
    for (int i = 0; i < 3 * 2 * 3; i++)
        CHECK(img.rgb[i] == 0.0f);
    c5_image_free(&img);
    CHECK(img.rgb == NULL);
    CHECK_INT(img.w, 0);
    CHECK_INT(img.h, 0);
    c5_image_free(&img); /* freeing twice is harmless */
    c5_image_free(NULL);
}

TEST(image_alloc_limits)
{
    static const int bad[][2] = {{0, 5},  {5, 0},     {-1, 3},    {3, -7},      {0, 0},
                                 {16385, 1}, {1, 16385}, {INT_MAX, INT_MAX}, {INT_MIN, 2}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        c5_err err = {{0}};
        c5_image img = {7, 7, (float *)&err}; /* garbage in: must be zeroed on failure */
        CHECK_INT(c5_image_alloc(&img, bad[i][0], bad[i][1], &err), -1);
        CHECK_HAS(err.msg, "out of range");
        CHECK(img.rgb == NULL);
        CHECK_INT(img.w, 0);
        CHECK_INT(img.h, 0);
        c5_image_free(&img);
    }
    /* The largest side is allowed. */
    c5_err err = {{0}};
    c5_image img;
    CHECK_INT(c5_image_alloc(&img, 16384, 1, &err), 0);
    c5_image_free(&img);
    CHECK_INT(c5_image_alloc(&img, 1, 16384, &err), 0);
    c5_image_free(&img);
}

TEST(image_exr_roundtrip_bit_exact)
{
    c5_err err = {{0}};
    c5_image img, back = {0, 0, NULL};
    CHECK_INT(c5_image_alloc(&img, 5, 3, &err), 0);
    static const float special[] = {0.0f,  -0.0f,   1.0f,     1.7f,      1234.5678f, 1e30f,
                                    1e-30f, 1e-42f /* subnormal */, -2.25f, 0.1f, 3.4e38f,
                                    -3.4e38f, 1.17549435e-38f /* smallest normal */, 0.999999f, 65504.0f};
    size_t ns = sizeof special / sizeof special[0];
    for (int i = 0; i < 5 * 3 * 3; i++)
        img.rgb[i] = i < (int)ns ? special[i] : 0.37f * (float)i - 3.0f;
    const char *p = c5t_path(0, "out.exr");
    CHECK_MSG(c5_image_write(p, &img, &err) == 0, "write: %s", err.msg);
    CHECK_MSG(c5_image_read(p, &back, &err) == 0, "read: %s", err.msg);
    CHECK_INT(back.w, 5);
    CHECK_INT(back.h, 3);
    for (int i = 0; i < 5 * 3 * 3; i++) {
        uint32_t a, b;
        memcpy(&a, &img.rgb[i], 4);
        memcpy(&b, &back.rgb[i], 4);
        CHECK_MSG(a == b, "value %d: wrote %.9g (0x%08x), read %.9g (0x%08x)", i,
                  (double)img.rgb[i], (unsigned)a, (double)back.rgb[i], (unsigned)b);
    }
    c5_image_free(&img);
    c5_image_free(&back);
}

TEST(image_png_quantisation)
{
    static const float v[] = {0.5f,       1.7f,       -0.2f,           0.998f,       0.0f,
                              1.0f,       -0.0f,      0.5f / 255.0f,   1.5f / 255.0f, 0.25f,
                              0.75f,      0.999f,     0.001f,          0.002f,        100.0f,
                              3.4e38f,    -3.4e38f,   127.5f / 255.0f, 0.3333f,       0.6667f,
                              0.9f};
    const int n = (int)(sizeof v / sizeof v[0]);
    /* The named cases, spelled out. */
    CHECK_INT(expected8(0.5f), 128);
    CHECK_INT(expected8(1.7f), 255);
    CHECK_INT(expected8(-0.2f), 0);
    CHECK_INT(expected8(0.998f), 254);

    c5_err err = {{0}};
    c5_image img, back = {0, 0, NULL};
    CHECK_INT(c5_image_alloc(&img, n, 2, &err), 0);
    /* Row 0: the values in R, G and B; row 1: in reverse order, so rows and channels are
     * distinguishable. */
    for (int x = 0; x < n; x++)
        for (int c = 0; c < 3; c++) {
            img.rgb[3 * x + c] = v[(x + c) % n];
            img.rgb[3 * (n + x) + c] = v[(n - 1 - x + c) % n];
        }
    const char *p = c5t_path(0, "q.png");
    CHECK_MSG(c5_image_write(p, &img, &err) == 0, "write: %s", err.msg);
    CHECK_MSG(c5_image_read(p, &back, &err) == 0, "read: %s", err.msg);
    CHECK_INT(back.w, n);
    CHECK_INT(back.h, 2);
    for (int i = 0; i < n * 2 * 3; i++) {
        int want = expected8(img.rgb[i]);
        CHECK_MSG(fabsf(back.rgb[i] * 255.0f - (float)want) < 1e-3f,
                  "value %d: %.9g should be stored as %d/255, read %.9g*255", i,
                  (double)img.rgb[i], want, (double)back.rgb[i] * 255.0);
        CHECK_NEAR(back.rgb[i], (float)want / 255.0f, 1e-6);
    }
    c5_image_free(&img);
    c5_image_free(&back);
}

TEST(image_extension_case_insensitive)
{
    c5_err err = {{0}};
    c5_image img, back = {0, 0, NULL};
    CHECK_INT(c5_image_alloc(&img, 4, 3, &err), 0);
    fill_pattern(&img);
    const char *p = c5t_path(0, "UP.PNG");
    CHECK_MSG(c5_image_write(p, &img, &err) == 0, "write: %s", err.msg);
    CHECK_MSG(c5_image_read(p, &back, &err) == 0, "read: %s", err.msg);
    CHECK_INT(back.w, 4);
    for (int i = 0; i < 4 * 3 * 3; i++)
        CHECK_NEAR(back.rgb[i], expected8(img.rgb[i]) / 255.0, 1e-6);
    c5_image_free(&back);
    p = c5t_path(1, "Up.Exr");
    CHECK_MSG(c5_image_write(p, &img, &err) == 0, "write: %s", err.msg);
    CHECK_MSG(c5_image_read(p, &back, &err) == 0, "read: %s", err.msg);
    CHECK(memcmp(back.rgb, img.rgb, sizeof(float) * 4 * 3 * 3) == 0);
    CHECK_INT(dir_count(NULL, 0, NULL), 2);
    c5_image_free(&img);
    c5_image_free(&back);
}

TEST(image_unsupported_extension)
{
    c5_err err = {{0}};
    c5_image img;
    char want[1200];
    CHECK_INT(c5_image_alloc(&img, 2, 2, &err), 0);
    const char *p = c5t_path(0, "out.xyz");
    CHECK_INT(c5_image_write(p, &img, &err), -1);
    snprintf(want, sizeof want, "%s: unsupported image extension '.xyz' (use .png or .exr)", p);
    CHECK_MSG(strcmp(err.msg, want) == 0, "message \"%s\"", err.msg);
    p = c5t_path(0, "out.JPG");
    CHECK_INT(c5_image_write(p, &img, &err), -1);
    snprintf(want, sizeof want, "%s: unsupported image extension '.JPG' (use .png or .exr)", p);
    CHECK_MSG(strcmp(err.msg, want) == 0, "message \"%s\"", err.msg);
    p = c5t_path(0, "out.png.tif");
    CHECK_INT(c5_image_write(p, &img, &err), -1);
    CHECK_HAS(err.msg, "'.tif'");
    p = c5t_path(0, "noext");
    CHECK_INT(c5_image_write(p, &img, &err), -1);
    CHECK_HAS(err.msg, p);
    CHECK_HAS(err.msg, "use .png or .exr");
    CHECK_INT(dir_count(NULL, 0, NULL), 0);
    c5_image_free(&img);
}

/* A NaN or an infinity is refused and nothing is written (a last line of defence: cref once
 * wrote +Inf into an EXR for a light of intensity 1e300). */
TEST(image_non_finite_refused_nothing_written)
{
    static const char *names[] = {"bad.png", "bad.exr"};
    static const float bad[] = {NAN, (float)INFINITY, -(float)INFINITY};
    static const char *const spelt[] = {"NaN", "+Inf", "-Inf"};
    for (int k = 0; k < 2; k++)
        for (int b = 0; b < 3; b++) {
            c5_err err = {{0}};
            c5_image img;
            char want[1200];
            CHECK_INT(c5_image_alloc(&img, 4, 3, &err), 0);
            fill_pattern(&img);
            img.rgb[3 * (1 * 4 + 2) + 1] = bad[b]; /* pixel (2,1), green */
            img.rgb[3 * (2 * 4 + 0) + 0] = NAN;    /* a later one: the first is reported */
            const char *p = c5t_path(0, names[k]);
            CHECK_INT(c5_image_write(p, &img, &err), -1);
            snprintf(want, sizeof want, "%s: image has %s at pixel (2,1)", p, spelt[b]);
            CHECK_MSG(strcmp(err.msg, want) == 0, "message \"%s\"", err.msg);
            CHECK(!file_exists(p));
            CHECK_INT(dir_count(NULL, 0, NULL), 0);
            c5_image_free(&img);
        }
}

TEST(image_failed_write_keeps_old_file)
{
    c5_err err = {{0}};
    c5_image img, back = {0, 0, NULL};
    CHECK_INT(c5_image_alloc(&img, 3, 3, &err), 0);
    fill_pattern(&img);
    const char *p = c5t_path(0, "keep.exr");
    CHECK_MSG(c5_image_write(p, &img, &err) == 0, "write: %s", err.msg);
    float old = img.rgb[4];
    img.rgb[4] = NAN;
    CHECK_INT(c5_image_write(p, &img, &err), -1);
    CHECK_MSG(c5_image_read(p, &back, &err) == 0, "read: %s", err.msg);
    CHECK(back.rgb[4] == old);
    CHECK_INT(dir_count(NULL, 0, NULL), 1);
    c5_image_free(&img);
    c5_image_free(&back);
}

TEST(image_overwrite_replaces)
{
    c5_err err = {{0}};
    c5_image img, back = {0, 0, NULL};
    CHECK_INT(c5_image_alloc(&img, 2, 1, &err), 0);
    const char *p = c5t_path(0, "o.png");
    CHECK_MSG(c5_image_write(p, &img, &err) == 0, "write: %s", err.msg);
    c5_image_free(&img);
    CHECK_INT(c5_image_alloc(&img, 3, 2, &err), 0);
    fill_pattern(&img);
    CHECK_MSG(c5_image_write(p, &img, &err) == 0, "write: %s", err.msg);
    CHECK_MSG(c5_image_read(p, &back, &err) == 0, "read: %s", err.msg);
    CHECK_INT(back.w, 3);
    CHECK_INT(back.h, 2);
    CHECK_NEAR(back.rgb[3 * 5 + 2], expected8(img.rgb[3 * 5 + 2]) / 255.0, 1e-6);
    CHECK_INT(dir_count(NULL, 0, NULL), 1);
    c5_image_free(&img);
    c5_image_free(&back);
}

TEST(image_missing_directory)
{
    static const char *names[] = {"nope/out.png", "nope/out.exr"};
    for (int k = 0; k < 2; k++) {
        c5_err err = {{0}};
        c5_image img;
        CHECK_INT(c5_image_alloc(&img, 2, 2, &err), 0);
        const char *p = c5t_path(0, names[k]);
        CHECK_INT(c5_image_write(p, &img, &err), -1);
        /* One line that starts with the path. */
        CHECK_MSG(strncmp(err.msg, p, strlen(p)) == 0 && err.msg[strlen(p)] == ':',
                  "message \"%s\" should start with \"%s:\"", err.msg, p);
        CHECK(strchr(err.msg, '\n') == NULL);
        /* The user's path only: never the temporary file the writer would have made. */
        CHECK_MSG(strstr(err.msg, ".tmp-") == NULL && strstr(err.msg, "folder ") != NULL, "%s", err.msg);
        CHECK_INT(c5_image_check_out(p, &err), -1);
        CHECK_MSG(strstr(err.msg, ".tmp-") == NULL && strstr(err.msg, "No such file") != NULL, "%s", err.msg);
        CHECK_INT(dir_count(NULL, 0, NULL), 0);
        c5_image_free(&img);
    }
}

TEST(image_no_temp_file_left)
{
    c5_err err = {{0}};
    c5_image img;
    char other[256];
    CHECK_INT(c5_image_alloc(&img, 8, 8, &err), 0);
    fill_pattern(&img);
    CHECK_MSG(c5_image_write(c5t_path(0, "a.png"), &img, &err) == 0, "write: %s", err.msg);
    int n = dir_count(other, sizeof other, "a.png");
    CHECK_MSG(n == 1 && !other[0], "%d entries, unexpected \"%s\"", n, other);
    CHECK_MSG(c5_image_write(c5t_path(0, "b.exr"), &img, &err) == 0, "write: %s", err.msg);
    CHECK_INT(dir_count(NULL, 0, NULL), 2);
    CHECK(file_exists(c5t_path(1, "a.png")));
    CHECK(file_exists(c5t_path(1, "b.exr")));
    c5_image_free(&img);
}

TEST(image_read_missing_file)
{
    c5_err err = {{0}};
    c5_image img = {9, 9, NULL};
    const char *p = c5t_path(0, "absent.png");
    CHECK_INT(c5_image_read(p, &img, &err), -1);
    CHECK_MSG(strncmp(err.msg, p, strlen(p)) == 0, "message \"%s\"", err.msg);
    CHECK(strchr(err.msg, '\n') == NULL);
    CHECK(img.rgb == NULL);
    CHECK_INT(img.w, 0);
    CHECK_INT(img.h, 0);
}

TEST(image_read_garbage_file)
{
    c5_err err = {{0}};
    c5_image img = {0, 0, NULL};
    const char *p = c5t_path(0, "junk.png");
    CHECK_INT(write_bytes(p, "this is not a png\n", 18), 0);
    CHECK_INT(c5_image_read(p, &img, &err), -1);
    CHECK_MSG(strncmp(err.msg, p, strlen(p)) == 0, "message \"%s\"", err.msg);
    CHECK(img.rgb == NULL);
}

TEST(image_read_grey_replicated)
{
    /* A 3x2 binary PGM: one channel. */
    static const unsigned char pgm[] = {'P', '5', '\n', '3', ' ', '2', '\n', '2', '5', '5', '\n',
                                        0, 51, 102, 153, 204, 255};
    c5_err err = {{0}};
    c5_image img = {0, 0, NULL};
    const char *p = c5t_path(0, "g.pgm");
    CHECK_INT(write_bytes(p, pgm, sizeof pgm), 0);
    CHECK_MSG(c5_image_read(p, &img, &err) == 0, "read: %s", err.msg);
    CHECK_INT(img.w, 3);
    CHECK_INT(img.h, 2);
    for (int i = 0; i < 6; i++)
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(img.rgb[3 * i + c], pgm[11 + i] / 255.0, 1e-6);
    c5_image_free(&img);
}

TEST(image_read_grey_alpha_and_rgba)
{
    /* 2x1 grey+alpha PNG: (51, alpha 255), (204, alpha 0). */
    static const unsigned char png_ga[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
        0x44, 0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x08, 0x04, 0x00, 0x00,
        0x00, 0x5e, 0x2b, 0xb7, 0x01, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78,
        0x9c, 0x63, 0x30, 0xfe, 0x7f, 0x86, 0x01, 0x00, 0x05, 0x66, 0x01, 0xff, 0x2e, 0x53,
        0x52, 0xba, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    /* 1x2 RGBA PNG: top (10,20,30, alpha 40), bottom (250,240,230, alpha 0). */
    static const unsigned char png_rgba[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
        0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x08, 0x06, 0x00, 0x00,
        0x00, 0x99, 0x81, 0xb6, 0x27, 0x00, 0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78,
        0x9c, 0x63, 0xe0, 0x12, 0x91, 0xd3, 0x60, 0xf8, 0xf5, 0xe1, 0x19, 0x03, 0x00, 0x0b,
        0x4a, 0x03, 0x35, 0x31, 0x74, 0x5b, 0x3e, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e,
        0x44, 0xae, 0x42, 0x60, 0x82};
    c5_err err = {{0}};
    c5_image img = {0, 0, NULL};
    const char *p = c5t_path(0, "ga.png");
    CHECK_INT(write_bytes(p, png_ga, sizeof png_ga), 0);
    CHECK_MSG(c5_image_read(p, &img, &err) == 0, "read: %s", err.msg);
    CHECK_INT(img.w, 2);
    CHECK_INT(img.h, 1);
    for (int c = 0; c < 3; c++) {
        CHECK_NEAR(img.rgb[c], 51 / 255.0, 1e-6);
        CHECK_NEAR(img.rgb[3 + c], 204 / 255.0, 1e-6); /* stored value, alpha not applied */
    }
    c5_image_free(&img);

    p = c5t_path(1, "rgba.png");
    CHECK_INT(write_bytes(p, png_rgba, sizeof png_rgba), 0);
    CHECK_MSG(c5_image_read(p, &img, &err) == 0, "read: %s", err.msg);
    CHECK_INT(img.w, 1);
    CHECK_INT(img.h, 2);
    static const int want[] = {10, 20, 30, 250, 240, 230}; /* top row first */
    for (int i = 0; i < 6; i++)
        CHECK_NEAR(img.rgb[i], want[i] / 255.0, 1e-6);
    c5_image_free(&img);
}

static long read_all(const char *path, unsigned char *buf, long cap)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    long n = (long)fread(buf, 1, (size_t)cap, f);
    fclose(f);
    return n;
}

/* The same image gives the same file bytes at any time: no timestamp in the file. */
TEST(image_same_bytes_on_every_write)
{
    const char *names[2][2] = {{"a.exr", "b.exr"}, {"a.png", "b.png"}};
    for (int k = 0; k < 2; k++) {
        c5_image img;
        c5_err err;
        CHECK(c5_image_alloc(&img, 4, 3, &err) == 0);
        for (int i = 0; i < 4 * 3 * 3; i++)
            img.rgb[i] = (float)i / 40;
        CHECK(c5_image_write(c5t_path(0, names[k][0]), &img, &err) == 0);
        struct timespec ts = {1, 100000000}; /* past the next whole second */
        nanosleep(&ts, NULL);
        CHECK(c5_image_write(c5t_path(1, names[k][1]), &img, &err) == 0);
        c5_image_free(&img);
        static unsigned char a[1 << 16], b[1 << 16];
        long na = read_all(c5t_path(0, names[k][0]), a, sizeof a), nb = read_all(c5t_path(1, names[k][1]), b, sizeof b);
        CHECK(na > 0 && na == nb);
        CHECK_MSG(memcmp(a, b, (size_t)na) == 0, "%s: two writes of one image differ", names[k][0]);
    }
}
