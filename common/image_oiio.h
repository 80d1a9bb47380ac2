/* The C API of libc5image.so (common/image_oiio.cpp), the OpenImageIO shim. Programs do not
 * link it: image_load.c opens it on the first image read or write, so that a run that writes
 * no image does not pay for loading OpenImageIO and the ~260 libraries it needs (half a
 * second a process). The contract of each is image.h's c5_image_write / c5_image_read. */
#ifndef C5_IMAGE_OIIO_H
#define C5_IMAGE_OIIO_H

#include "image.h"

int c5_image_oiio_write(const char *path, const c5_image *img, c5_err *err);
int c5_image_oiio_read(const char *path, c5_image *img, c5_err *err);

#endif
