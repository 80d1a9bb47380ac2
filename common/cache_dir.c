/* cube5's cache folder (cache_dir.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atomic_file.h"
#include "cache_dir.h"

int c5_cache_dir(char *out, size_t n)
{
    const char *d = getenv("C5_CACHE_DIR"), *x = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (d && (!*d || !strcmp(d, "off")))
        return -1;
    if (d)
        snprintf(out, n, "%s", d);
    else if (x && *x)
        snprintf(out, n, "%s/cube5", x);
    else if (home && *home)
        snprintf(out, n, "%s/.cache/cube5", home);
    else
        return -1;
    c5_err e;
    return c5_output_dir(out, &e);
}

uint64_t c5_cache_hash(const char *s)
{
    uint64_t h = 0xcbf29ce484222325u; /* FNV-1a */
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 0x100000001b3u;
    return h;
}
