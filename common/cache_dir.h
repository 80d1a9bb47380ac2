/* cube5's cache folder: what is derived from a volume once and kept for later runs (the block
 * ranges of a volume file, block_range.h; an out-of-core grid's cells, rtl_model/mem/
 * cell_store.h). $C5_CACHE_DIR, else $XDG_CACHE_HOME/cube5, else $HOME/.cache/cube5;
 * C5_CACHE_DIR=off (or empty) keeps none. Nothing is ever written beside the user's files. */
#ifndef C5_CACHE_DIR_H
#define C5_CACHE_DIR_H

#include <stddef.h>
#include <stdint.h>

/* The folder (created as mkdir -p) into out: 0, or -1 (none wanted, or none can be made). */
int c5_cache_dir(char *out, size_t n);
/* A 64-bit hash of an identity string, for a cache file's name (the file holds the string
 * itself, which is what decides). */
uint64_t c5_cache_hash(const char *s);

#endif
