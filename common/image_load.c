/* image.h's reading and writing, through libc5image.so (image_oiio.h), opened on first use.
 * The library is looked for beside the program, one folder up (build/tests/unit), in
 * ../lib/cube5 (an installed tree), then in C5_IMAGE_LIBDIR (make install's LIBDIR/cube5);
 * C5_IMAGE_LIB names it outright. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image_oiio.h"

#ifndef C5_IMAGE_LIBDIR
#define C5_IMAGE_LIBDIR "/usr/local/lib/cube5"
#endif
#define C5_IMAGE_SO "libc5image.so"

typedef int (*write_fn)(const char *, const c5_image *, c5_err *);
typedef int (*read_fn)(const char *, c5_image *, c5_err *);

static pthread_once_t once = PTHREAD_ONCE_INIT;
static write_fn lib_write;
static read_fn lib_read;
static char why[PATH_MAX + 256];

static void *try_open(const char *path)
{
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h && !why[0])
        snprintf(why, sizeof why, "%s", dlerror());
    return h;
}

static void load(void)
{
    void *h = NULL;
    const char *env = getenv("C5_IMAGE_LIB");
    if (env && *env) {
        h = try_open(env);
    } else {
        char exe[PATH_MAX], path[PATH_MAX + 64];
        ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
        if (n > 0) {
            exe[n] = 0;
            char *slash = strrchr(exe, '/');
            if (slash)
                *slash = 0;
            const char *rel[] = {"/", "/../", "/../lib/cube5/"};
            for (size_t i = 0; !h && i < sizeof rel / sizeof rel[0]; i++) {
                snprintf(path, sizeof path, "%s%s" C5_IMAGE_SO, exe, rel[i]);
                if (access(path, F_OK) == 0)
                    h = try_open(path);
            }
        }
        if (!h && access(C5_IMAGE_LIBDIR "/" C5_IMAGE_SO, F_OK) == 0)
            h = try_open(C5_IMAGE_LIBDIR "/" C5_IMAGE_SO);
    }
    if (h) {
        *(void **)&lib_write = dlsym(h, "c5_image_oiio_write");
        *(void **)&lib_read = dlsym(h, "c5_image_oiio_read");
        if (!lib_write || !lib_read)
            snprintf(why, sizeof why, "it lacks c5_image_oiio_write/read");
    } else if (!why[0]) {
        snprintf(why, sizeof why, "not beside the program, in ../lib/cube5 nor in %s (C5_IMAGE_LIB names it)",
                 C5_IMAGE_LIBDIR);
    }
}

static int ready(const char *path, c5_err *err)
{
    pthread_once(&once, load);
    if (lib_write && lib_read)
        return 0;
    return c5_fail(err, "%s: the image library " C5_IMAGE_SO " (OpenImageIO) cannot be loaded: %s", path ? path : "image",
                   why);
}

static pthread_t preloader;
static int preloading;

static void *preload_main(void *arg)
{
    (void)arg;
    pthread_once(&once, load);
    return NULL;
}

void c5_image_preload(void)
{
    if (!preloading && pthread_create(&preloader, NULL, preload_main, NULL) == 0)
        preloading = 1;
}

void c5_image_preload_wait(void)
{
    if (preloading)
        pthread_join(preloader, NULL);
    preloading = 0;
}

int c5_image_write(const char *path, const c5_image *img, c5_err *err)
{
    return ready(path, err) != 0 ? -1 : lib_write(path, img, err);
}

int c5_image_read(const char *path, c5_image *img, c5_err *err)
{
    if (img) {
        img->w = img->h = 0;
        img->rgb = NULL;
    }
    return ready(path, err) != 0 ? -1 : lib_read(path, img, err);
}
