/* cube5's cache folder: what is derived from a volume once and kept for later runs (the block
 * ranges of a volume file, block_range.h; an out-of-core grid's cells, rtl_model/mem/
 * cell_store.h). $C5_CACHE_DIR, else $XDG_CACHE_HOME/cube5, else $HOME/.cache/cube5;
 * C5_CACHE_DIR=off (or empty) keeps none. Nothing is ever written beside the user's files. */
#ifndef C5_CACHE_DIR_H
#define C5_CACHE_DIR_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"

/* The folder (created as mkdir -p) into out: 0, or -1 (none wanted, or none can be made). */
int c5_cache_dir(char *out, size_t n);
/* The most the folder holds: C5_CACHE_MAX (a byte count as C5_MEM_BUDGET's), default
 * C5_CACHE_MAX_DEFAULT; -1 with err when set but not a byte count. */
#define C5_CACHE_MAX_DEFAULT ((size_t)64 << 30)
int c5_cache_max(size_t *out, c5_err *err);
/* Room for a new file of `bytes` in dir: the folder's least recently used cache files are
 * removed until it holds at most C5_CACHE_MAX with it, and the file system keeps 1 GiB
 * free beside it. 0, or -1: it cannot have the room (the file is larger than the cap, or
 * the disk too full): the caller goes without. */
int c5_cache_make_room(const char *dir, size_t bytes);
/* A cache file was used: its time moves up in the least-recently-used order. */
void c5_cache_touch(const char *path);
/* A 64-bit hash of an identity string, for a cache file's name (the file holds the string
 * itself, which is what decides). */
uint64_t c5_cache_hash(const char *s);

#endif
