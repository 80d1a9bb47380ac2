/* Runs a harness (fuzz/fuzz.h) over files without libFuzzer: each argument is a file or a
 * folder of files, each file one input. `make test` runs it over fuzz/corpus/NAME/ with the
 * normal toolchain, `make asan` under AddressSanitizer. Exit 0 when every input ran; a
 * finding aborts (or the sanitizer ends the process). */
#include <dirent.h>
#include <sys/stat.h>

#include "fuzz.h"

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "replay: %s: cannot open\n", path);
        return -1;
    }
    size_t cap = 1 << 16, n = 0;
    uint8_t *buf = malloc(cap);
    for (size_t r; buf && (r = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += r;
        if (n == cap) {
            uint8_t *b = realloc(buf, cap *= 2);
            if (!b)
                free(buf);
            buf = b;
        }
    }
    fclose(f);
    if (!buf) {
        fprintf(stderr, "replay: %s: out of memory\n", path);
        return -1;
    }
    LLVMFuzzerTestOneInput(buf, n);
    free(buf);
    return 0;
}

int main(int argc, char **argv)
{
    int files = 0;
    for (int i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "replay: %s: no such file or folder\n", argv[i]);
            return 2;
        }
        if (!S_ISDIR(st.st_mode)) {
            if (run_file(argv[i]) != 0)
                return 2;
            files++;
            continue;
        }
        struct dirent **names;
        int n = scandir(argv[i], &names, NULL, alphasort);
        if (n < 0) {
            fprintf(stderr, "replay: %s: cannot list\n", argv[i]);
            return 2;
        }
        for (int k = 0; k < n; k++) {
            char p[4096];
            int skip = names[k]->d_name[0] == '.';
            if (!skip && (size_t)snprintf(p, sizeof p, "%s/%s", argv[i], names[k]->d_name) < sizeof p) {
                if (run_file(p) != 0)
                    return 2;
                files++;
            }
            free(names[k]);
        }
        free(names);
    }
    printf("replayed %d input(s)\n", files);
    return files ? 0 : 2;
}
