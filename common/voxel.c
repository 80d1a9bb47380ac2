/* The voxel types, the extents accepted and the checked opening of a volume file
 * (voxel.h). */
#include "voxel.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int c5_mul_size(size_t a, size_t b, size_t *r)
{
    if (a != 0 && b > SIZE_MAX / a)
        return -1;
    *r = a * b;
    return 0;
}

static int dims_overflow(const size_t dims[3], size_t *count)
{
    size_t n = 1;
    for (int i = 0; i < 3; i++)
        if (c5_mul_size(n, dims[i], &n) != 0)
            return -1;
    *count = n;
    return 0;
}

static int dims_in_range(const size_t dims[3])
{
    for (int i = 0; i < 3; i++)
        if (dims[i] < 1 || dims[i] > C5_VOLUME_MAX_DIM)
            return 0;
    return 1;
}

int c5_dims_product(const size_t dims[3], size_t *count)
{
    size_t n;
    if (!dims_in_range(dims) || dims_overflow(dims, &n) != 0 || n > C5_VOLUME_MAX_VOXELS)
        return -1;
    *count = n;
    return 0;
}

int c5_dims_fail(const char *path, const size_t d[3], c5_err *err)
{
    size_t n = 0;
    if (dims_overflow(d, &n) != 0)
        return c5_fail(err, "%s: dims %zux%zux%zu overflow", path, d[0], d[1], d[2]);
    if (!dims_in_range(d))
        return c5_fail(err, "%s: dims %zux%zux%zu: every dim must be 1..%u", path, d[0], d[1],
                       d[2], C5_VOLUME_MAX_DIM);
    return c5_fail(err, "%s: dims %zux%zux%zu: %zu voxels exceed the limit of %zu", path, d[0],
                   d[1], d[2], n, (size_t)C5_VOLUME_MAX_VOXELS);
}

int c5_open_regular(const char *path, const char *where, long long *size, c5_err *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return c5_fail(err, "%s: cannot open: %s", where, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        c5_fail(err, "%s: cannot stat: %s", where, strerror(errno));
        close(fd);
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        c5_fail(err, "%s: not a regular file", where);
        close(fd);
        return -1;
    }
    *size = (long long)st.st_size;
    return fd;
}

