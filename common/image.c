/* Image storage. Reading and writing: image_load.c, through image_oiio.cpp. */
#include "image.h"

#include "atomic_file.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define C5_IMAGE_MAX_SIDE 16384

/* On success img holds a zero-filled w*h RGB image; on failure img is zeroed (safe to free). */
int c5_image_alloc(c5_image *img, int w, int h, c5_err *err)
{
    if (!img)
        return c5_fail(err, "image: internal error: no image to allocate");
    memset(img, 0, sizeof *img);
    if (w < 1 || w > C5_IMAGE_MAX_SIDE || h < 1 || h > C5_IMAGE_MAX_SIDE)
        return c5_fail(err, "image size %dx%d out of range (each side must be 1..%d)", w, h,
                       C5_IMAGE_MAX_SIDE);
    /* Cannot overflow with the limits above, but keep the check honest on any size_t. */
    if ((size_t)w > SIZE_MAX / sizeof(float) / 3 / (size_t)h)
        return c5_fail(err, "image size %dx%d too large for this machine", w, h);
    size_t n = (size_t)w * (size_t)h * 3;
    float *rgb = calloc(n, sizeof *rgb);
    if (!rgb)
        return c5_fail(err, "out of memory allocating a %dx%d image (%zu bytes)", w, h,
                       n * sizeof *rgb);
    img->w = w;
    img->h = h;
    img->rgb = rgb;
    return 0;
}

void c5_image_free(c5_image *img)
{
    if (!img)
        return;
    free(img->rgb);
    memset(img, 0, sizeof *img);
}

int c5_image_check_out(const char *path, c5_err *err)
{
    if (!path || !*path)
        return c5_fail(err, "image: no output path given");
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path, *dot = strrchr(base, '.');
    if (!dot)
        return c5_fail(err, "%s: missing image extension (use .png or .exr)", path);
    if (strcasecmp(dot, ".png") && strcasecmp(dot, ".exr"))
        return c5_fail(err, "%s: unsupported image extension '%s' (use .png or .exr)", path, dot);
    return c5_output_check(path, err);
}
