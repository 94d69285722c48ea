/* Runs a libFuzzer target's LLVMFuzzerTestOneInput over files, without
 * libFuzzer: the regression test of tests/fuzz in ordinary builds.
 *
 *   fuzz_scene_replay PATH...
 *
 * Each PATH is a file or a folder (its regular files, not recursively, in
 * name order; names starting with '.' are skipped). Prints one line per
 * folder and a total; a crash, a sanitizer report or a broken contract
 * (the target aborts) fails the test. Exit status: 0, or 1 when a path
 * cannot be read or nothing was replayed. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
/* Optional in a target (fuzz_scene has one). */
int LLVMFuzzerInitialize(int *argc, char ***argv) __attribute__((weak));

/* Largest input replayed (libFuzzer's default -max_len is far smaller). */
#define REPLAY_MAX_BYTES (16L << 20)

static int replay_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    uint8_t *buf;
    long n;
    if (!fp) {
        perror(path);
        return -1;
    }
    if (fseek(fp, 0, SEEK_END) != 0 || (n = ftell(fp)) < 0 || n > REPLAY_MAX_BYTES ||
        fseek(fp, 0, SEEK_SET) != 0) {
        fprintf(stderr, "%s: cannot read (or larger than %ld bytes)\n", path, REPLAY_MAX_BYTES);
        fclose(fp);
        return -1;
    }
    /* an exact-size copy, so that ASan sees any read past the end */
    buf = malloc(n > 0 ? (size_t)n : 1);
    if (!buf || fread(buf, 1, (size_t)n, fp) != (size_t)n) {
        fprintf(stderr, "%s: cannot read\n", path);
        free(buf);
        fclose(fp);
        return -1;
    }
    fclose(fp);
    LLVMFuzzerTestOneInput(buf, (size_t)n);
    free(buf);
    return 0;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Replays the files of a folder; returns how many, or -1. */
static int replay_dir(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char **names = NULL, path[4096];
    int n = 0, cap = 0, i, done = 0, rc = 0;
    if (!d) {
        perror(dir);
        return -1;
    }
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        if (n == cap) {
            char **g = realloc(names, sizeof *names * (size_t)(cap = cap ? 2 * cap : 64));
            if (!g) {
                rc = -1;
                break;
            }
            names = g;
        }
        if (!(names[n] = strdup(e->d_name))) {
            rc = -1;
            break;
        }
        n++;
    }
    closedir(d);
    if (rc == 0)
        qsort(names, (size_t)n, sizeof *names, by_name);
    for (i = 0; i < n; i++) {
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        if (rc == 0 && stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
            if (replay_file(path))
                rc = -1;
            else
                done++;
        }
        free(names[i]);
    }
    free(names);
    if (rc == 0)
        printf("%s: %d inputs replayed\n", dir, done);
    return rc ? -1 : done;
}

int main(int argc, char **argv)
{
    int i, total = 0, failed = 0;
    if (LLVMFuzzerInitialize)
        LLVMFuzzerInitialize(&argc, &argv);
    for (i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            perror(argv[i]);
            failed = 1;
        } else if (S_ISDIR(st.st_mode)) {
            int n = replay_dir(argv[i]);
            if (n < 0)
                failed = 1;
            else
                total += n;
        } else if (replay_file(argv[i]) == 0) {
            total++;
        } else {
            failed = 1;
        }
    }
    printf("%d inputs replayed without a crash%s\n", total, failed ? "; some paths failed" : "");
    return failed || total == 0;
}
