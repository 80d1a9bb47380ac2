/* Images: linear RGB floats, row 0 at the top. Written and read through OpenImageIO
 * (common/image_oiio.cpp, the only C++ in the project, a library opened on first use:
 * image_load.c). */
#ifndef C5_IMAGE_H
#define C5_IMAGE_H

#include "err.h"

typedef struct {
    int w, h;
    float *rgb; /* w*h*3, row-major, top row first */
} c5_image;

int c5_image_alloc(c5_image *img, int w, int h, c5_err *err);
void c5_image_free(c5_image *img);

/* The format follows the extension: .png (8-bit, values clamped to [0,1], rounded to
 * nearest of 255 levels, no gamma) or .exr (32-bit float, exact). Anything else is an error. */
int c5_image_write(const char *path, const c5_image *img, c5_err *err);
/* What c5_image_write refuses whatever the image, checked before the work that makes it: the
 * extension, and a folder that is missing, not a folder or not writable. */
int c5_image_check_out(const char *path, c5_err *err);
/* The library opened on a thread of its own, beside the caller's work (opening it is some
 * 0.2 s of the dynamic linker's for OpenImageIO's dependencies); c5_image_preload_wait
 * joins it. Whatever happens on that thread, the first read or write reports it as it
 * would have without. From one thread (a program's main). */
void c5_image_preload(void);
void c5_image_preload_wait(void);
/* Reads any format OpenImageIO knows into RGB floats (extra channels dropped, grey
 * replicated). Used by tests and comparisons. */
int c5_image_read(const char *path, c5_image *img, c5_err *err);

#endif
