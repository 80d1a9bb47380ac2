/* Scene taps that keep a uniform sample of a block's transactions (blocks.h). */
#include <stdlib.h>

#include "blocks.h"
#include "reservoir.h"

int c5_vsample_begin(c5_vscene *v, int slot, size_t rec_size, uint64_t salt)
{
    c5_reservoir *r = malloc(sizeof *r);
    if (!r || c5_res_init(r, rec_size, (size_t)v->set->count, v->seed ^ salt) != 0) {
        free(r);
        return -1;
    }
    v->st[slot] = r;
    return 0;
}

void c5_vsample_offer(c5_vscene *v, int slot, const void *rec) { c5_res_offer(v->st[slot], rec); }

void c5_vsample_end(c5_vscene *v, int slot, const c5_vblock *b, void (*write)(c5_vfile *f, const void *rec),
                    json_t *config)
{
    c5_reservoir *r = v->st[slot];
    c5_vfile *f = c5_vfile_open(v->set, b, v->scene, v->scene, NULL);
    if (f) {
        c5_res_sort(r);
        for (size_t i = 0; i < r->n; i++)
            write(f, c5_res_at(r, i));
        if (config)
            c5_vfile_set(f, "config", config);
        c5_vfile_set(f, "offered", json_integer((json_int_t)r->seen));
        c5_vfile_close(f);
    } else {
        json_decref(config);
    }
    c5_res_free(r);
    free(r);
    v->st[slot] = NULL;
}
