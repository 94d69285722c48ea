/* curray cli: stale frame files, the run hash and resuming (resume.h). */
#include "resume.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <zlib.h>

#include "../base/fsutil.h"
#include "../output/types.h"

/* If name is a frame file "<t>_<k>.<ext>", its type and frame; else -1. */
static int cr_parse_frame_name(const char *name, char *t, long *k)
{
    char ext[8], again[64];
    int end = 0;
    long v;
    if (sscanf(name, "%c_%ld.%7[a-z]%n", t, &v, ext, &end) != 3 || name[end] != '\0' || v < 0 ||
        v > 0x7fffffffL)
        return -1;
    /* the canonical spelling only: "c_07.png" is not a frame file */
    if (cr_output_file_name(*t, (int)v, again, sizeof again) != 0 || strcmp(again, name) != 0)
        return -1;
    *k = v;
    return 0;
}

static int cr_long_cmp(const void *a, const void *b)
{
    long x = *(const long *)a, y = *(const long *)b;
    return (x > y) - (x < y);
}

/* "4-7, 9" from sorted frame numbers. */
static void cr_put_ranges(FILE *fp, const long *v, size_t n)
{
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j + 1 < n && v[j + 1] == v[j] + 1)
            j++;
        fprintf(fp, "%s%ld", i ? ", " : "", v[i]);
        if (j > i)
            fprintf(fp, "-%ld", v[j]);
        i = j + 1;
    }
}

int cr_stale_scan(const char *dir, int frames, const char *types, char **text)
{
    DIR *d;
    struct dirent *e;
    int nt = cr_output_type_count(); /* indexed like the table of output types */
    long **ks;
    size_t *nk, *cap;
    int total = 0, rc = 0;
    size_t len = 0;
    FILE *fp;

    *text = NULL;
    d = opendir(dir);
    if (!d)
        return 0;
    ks = calloc((size_t)nt, sizeof *ks);
    nk = calloc((size_t)nt, sizeof *nk);
    cap = calloc((size_t)nt, sizeof *cap);
    if (!ks || !nk || !cap) {
        closedir(d);
        free(ks);
        free(nk);
        free(cap);
        return -1;
    }
    while ((e = readdir(d)) != NULL) {
        char t;
        long k;
        size_t i;
        if (cr_parse_frame_name(e->d_name, &t, &k) != 0)
            continue;
        if (strchr(types, t) && k < frames)
            continue; /* this run writes it */
        for (i = 0; cr_output_type_at((int)i)->letter != t; i++)
            ;
        if (nk[i] == cap[i]) {
            size_t c = cap[i] ? 2 * cap[i] : 16;
            long *p = realloc(ks[i], c * sizeof *p);
            if (!p) {
                rc = -1;
                break;
            }
            ks[i] = p;
            cap[i] = c;
        }
        ks[i][nk[i]++] = k;
        total++;
    }
    closedir(d);
    if (rc == 0 && total > 0 && (fp = open_memstream(text, &len)) != NULL) {
        int first = 1;
        for (int i = 0; i < nt; i++) {
            if (!nk[i])
                continue;
            qsort(ks[i], nk[i], sizeof *ks[i], cr_long_cmp);
            fprintf(fp, "%s%c_<k>.%s for k = ", first ? "" : "; ", cr_output_type_at(i)->letter,
                    cr_output_type_at(i)->file);
            cr_put_ranges(fp, ks[i], nk[i]);
            first = 0;
        }
        if (fclose(fp) != 0) {
            free(*text);
            *text = NULL;
            rc = -1;
        }
    } else if (rc == 0 && total > 0) {
        rc = -1;
    }
    for (int i = 0; i < nt; i++)
        free(ks[i]);
    free(ks);
    free(nk);
    free(cap);
    return rc ? -1 : total;
}

int cr_remove_dead_temps(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    if (!d)
        return 0;
    while ((e = readdir(d)) != NULL) {
        const char *tmp = e->d_name[0] == '.' ? strstr(e->d_name, ".tmp.") : NULL;
        char path[4096];
        long pid;
        char inner[256], t;
        long k;
        size_t len = tmp ? (size_t)(tmp - e->d_name) - 1 : 0;
        if (!tmp || len == 0 || len >= sizeof inner ||
            sscanf(tmp, ".tmp.%ld.", &pid) != 1 || pid <= 0 || pid == (long)getpid())
            continue;
        /* only curray's own outputs: a frame file, info.txt or a video */
        memcpy(inner, e->d_name + 1, len);
        inner[len] = '\0';
        if (cr_parse_frame_name(inner, &t, &k) != 0 && strcmp(inner, "info.txt") != 0 &&
            (len < 4 || strcmp(inner + len - 4, ".mp4") != 0))
            continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue; /* still running, or not ours to judge */
        if (cr_path_join(path, sizeof path, dir, e->d_name) == 0 && unlink(path) == 0)
            n++;
    }
    closedir(d);
    return n;
}

/* FNV-1a, 64 bits. */
static void cr_fnv(uint64_t *h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        *h ^= p[i];
        *h *= 0x100000001b3ULL;
    }
}

static int cr_fnv_file(uint64_t *h, const char *path, cr_err *err)
{
    unsigned char buf[65536];
    size_t n;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return cr_err_set(err, "run hash: cannot read '%s': %s", path, strerror(errno));
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0)
        cr_fnv(h, buf, n);
    n = (size_t)ferror(fp);
    fclose(fp);
    if (n)
        return cr_err_set(err, "run hash: cannot read '%s'", path);
    return 0;
}

int cr_run_hash(const cr_scene *scene, const cr_sysconfig *cfg, long width, long height,
                long frames, const char *types, int use_cuda, const char *extra, char out[17],
                cr_err *err)
{
    uint64_t h = 0xcbf29ce484222325ULL;
    char text[1024], settings[512], set[32] = "";
    size_t n = 0;
    /* the set of output types, in the table's order (types.h) */
    for (int i = 0; i < cr_output_type_count(); i++)
        if (strchr(types, cr_output_type_at(i)->letter) && n + 1 < sizeof set)
            set[n++] = cr_output_type_at(i)->letter;
    set[n] = '\0';
    if (scene->path && cr_fnv_file(&h, scene->path, err))
        return -1;
    if (scene->has_sky && scene->sky_image && cr_fnv_file(&h, scene->sky_image, err))
        return -1;
    cr_trace_settings_hash_text(&cfg->raytracer, settings, sizeof settings);
    snprintf(text, sizeof text, "|%s|size %ldx%ld frames %ld types %s backend %s|%s", settings,
             width, height, frames, set, use_cuda ? "cuda" : "cpu", extra ? extra : "");
    cr_fnv(&h, text, strlen(text));
    snprintf(out, 17, "%016" PRIx64, h);
    return 0;
}

/* The whole file, NUL-terminated; NULL with errno when it cannot be read. */
static char *cr_read_text(const char *path)
{
    FILE *fp = fopen(path, "rb");
    char *buf = NULL;
    size_t len = 0, cap = 0, n;
    if (!fp)
        return NULL;
    for (;;) {
        if (cap - len < 4097) {
            char *p = realloc(buf, cap ? 2 * cap : 65536);
            if (!p) {
                free(buf);
                fclose(fp);
                errno = ENOMEM;
                return NULL;
            }
            buf = p;
            cap = cap ? 2 * cap : 65536;
        }
        n = fread(buf + len, 1, cap - len - 1, fp);
        len += n;
        if (n == 0)
            break;
    }
    if (ferror(fp)) {
        free(buf);
        fclose(fp);
        errno = EIO;
        return NULL;
    }
    fclose(fp);
    buf[len] = '\0';
    return buf;
}

/* A frame record's first line "Frame <k>\n" at p: k (0 <= k < frames), or
 * -1. Reads only that line: the scan of info.txt stays linear in its size. */
/* The newline before the first line at or after p (below end) that starts
 * with prefix, or NULL. Bounded by end, never by the string's length: strstr
 * and strchr would measure the rest of the file at each call (a sanitizer's
 * interceptors do), which makes a scan of many records quadratic. */
static char *cr_find_line(char *p, const char *end, const char *prefix)
{
    size_t n = strlen(prefix);
    for (char *nl; (nl = memchr(p, '\n', (size_t)(end - p))) != NULL; p = nl + 1)
        if ((size_t)(end - nl - 1) >= n && memcmp(nl + 1, prefix, n) == 0)
            return nl;
    return NULL;
}

static int cr_record_frame(const char *p, int frames)
{
    long k = 0;
    int digits = 0;
    if (strncmp(p, "Frame ", 6) != 0)
        return -1;
    for (p += 6; *p >= '0' && *p <= '9' && digits < 10; p++, digits++)
        k = 10 * k + (*p - '0');
    if (digits == 0 || *p != '\n' || k >= frames)
        return -1;
    return (int)k;
}

int cr_info_path_check(const char *dir, cr_err *err)
{
    char path[4096];
    struct stat st;
    if (cr_path_join(path, sizeof path, dir, "info.txt") != 0 || lstat(path, &st) != 0 ||
        !S_ISDIR(st.st_mode))
        return 0;
    return cr_err_set(err,
                      "%s is a folder, where this run writes its summary info.txt; move it "
                      "away, or choose another output folder with -o",
                      path);
}

int cr_resume_load(cr_resume *r, const char *dir, const char *hash, int frames, cr_err *err)
{
    char path[4096], *text, *p, *line;
    const char *end, *key = "\n  run hash ";
    memset(r, 0, sizeof *r);
    r->frames = frames;
    if (cr_path_join(path, sizeof path, dir, "info.txt") != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    text = cr_read_text(path);
    if (!text) {
        if (errno == ENOENT)
            return cr_err_set(err,
                              "--resume: no earlier run to resume in %s (no info.txt); run "
                              "without --resume",
                              dir);
        return cr_err_set(err, "--resume: cannot read %s: %s", path, strerror(errno));
    }
    p = strstr(text, key);
    if (!p) {
        free(text);
        return cr_err_set(err,
                          "--resume: %s has no run hash (written by an older curray, or not "
                          "by curray); run without --resume",
                          path);
    }
    p += strlen(key);
    p += strspn(p, " ");
    if (strncmp(p, hash, 16) != 0) {
        char old[17];
        snprintf(old, sizeof old, "%.16s", p);
        free(text);
        return cr_err_set(err,
                          "--resume: %s is from another run: its run hash is %s, this run's "
                          "is %s (the scene or sky image, the raytracer configuration, the "
                          "size, the frame count, the output types or the backend differ); "
                          "run without --resume, or use another output folder",
                          path, old, hash);
    }
    if ((p = strstr(text, "\nStarted ")) != NULL || strncmp(text, "Started ", 8) == 0) {
        p = p ? p + 9 : text + 8;
        p += strspn(p, " ");
        snprintf(r->started, sizeof r->started, "%.*s", (int)strcspn(p, "\n"), p);
    }
    r->order = calloc((size_t)frames, sizeof *r->order);
    r->body = calloc((size_t)frames, sizeof *r->body);
    if (!r->order || !r->body) {
        free(text);
        cr_resume_free(r);
        return cr_err_set(err, "--resume: out of memory");
    }
    /* records: "Frame <k>\n" ... up to the line "Finished ..."; every step
     * moves forward, each byte is looked at a bounded number of times */
    end = text + strlen(text);
    for (line = text; line && *line;) {
        int k = cr_record_frame(line, frames);
        char *fin, *nl;
        if (k < 0) {
            nl = memchr(line, '\n', (size_t)(end - line));
            line = nl ? nl + 1 : NULL;
            continue;
        }
        fin = cr_find_line(line, end, "Finished ");
        if (!fin)
            break; /* cannot happen with whole records; take nothing more */
        if (!r->body[k]) {
            r->body[k] = strndup(line, (size_t)(fin + 1 - line));
            if (!r->body[k]) {
                free(text);
                cr_resume_free(r);
                return cr_err_set(err, "--resume: out of memory");
            }
            r->order[r->n_records++] = k;
        }
        line = fin + 1;
    }
    free(text);
    return 0;
}

/* The label of a file line of a frame record ("  %-22s " of "frame file") */
#define CR_FILE_LABEL "  frame file             "

/* Size and CRC-32 (zlib) of the regular file open as fd. */
static int cr_file_sum(int fd, long long *size, unsigned long *crc)
{
    static const size_t chunk = 1 << 20;
    unsigned char *buf = malloc(chunk);
    uLong c = crc32(0L, Z_NULL, 0);
    long long n_all = 0;
    ssize_t n;
    if (!buf)
        return -1;
    while ((n = read(fd, buf, chunk)) > 0) {
        c = crc32(c, buf, (uInt)n);
        n_all += n;
    }
    free(buf);
    if (n < 0)
        return -1;
    *size = n_all;
    *crc = (unsigned long)c;
    return 0;
}

int cr_frame_files_describe(const char *dir, int k, const char *types, char **text, cr_err *err)
{
    size_t len = 0;
    FILE *fp;
    *text = NULL;
    if (!*types)
        return 0;
    fp = open_memstream(text, &len);
    if (!fp)
        return cr_err_set(err, "out of memory");
    for (const char *t = types; *t; t++) {
        char name[64], path[4096];
        long long size;
        unsigned long crc;
        int fd, rc;
        if (cr_output_file_name(*t, k, name, sizeof name) != 0 ||
            cr_path_join(path, sizeof path, dir, name) != 0)
            continue;
        fd = open(path, O_RDONLY | O_CLOEXEC);
        rc = fd < 0 ? -1 : cr_file_sum(fd, &size, &crc);
        if (fd >= 0)
            close(fd);
        if (rc != 0) {
            fclose(fp);
            free(*text);
            *text = NULL;
            return cr_err_set(err, "cannot read back '%s' for its checksum: %s", path,
                              strerror(errno));
        }
        fprintf(fp, CR_FILE_LABEL "%s %lld bytes, crc32 %08lx\n", name, size, crc);
    }
    if (fclose(fp) != 0) {
        free(*text);
        *text = NULL;
        return cr_err_set(err, "out of memory");
    }
    return 0;
}

/* snprintf into why, where a long path is cut short on purpose */
static void cr_why(char *why, size_t n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static void cr_why(char *why, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, n, fmt, ap);
    va_end(ap);
}

/* Does frame k's file of type t match its line in body? 1 yes; 0 no, with
 * why; -1 when it is a folder (with why): nothing can replace it. */
static int cr_frame_file_matches(const char *body, const char *dir, char t, int k, char *why,
                                 size_t n)
{
    char name[64], path[4096], want[96];
    const char *line;
    long long size, rec_size;
    unsigned long crc, rec_crc;
    struct stat st;
    int fd, rc;
    if (cr_output_file_name(t, k, name, sizeof name) != 0 ||
        cr_path_join(path, sizeof path, dir, name) != 0)
        return 1;
    snprintf(want, sizeof want, "\n" CR_FILE_LABEL "%s ", name);
    line = strstr(body, want);
    if (lstat(path, &st) != 0) {
        cr_why(why, n, "%s is missing", name);
        return 0;
    }
    if (S_ISDIR(st.st_mode)) {
        cr_why(why, n, "%s is a folder, where frame %d's file belongs", path, k);
        return -1;
    }
    if (S_ISLNK(st.st_mode)) {
        cr_why(why, n, "%s is a symbolic link, not a file curray wrote", name);
        return 0;
    }
    if (!S_ISREG(st.st_mode)) {
        cr_why(why, n, "%s is not a regular file", name);
        return 0;
    }
    if (!line || sscanf(line + strlen(want), "%lld bytes, crc32 %8lx", &rec_size, &rec_crc) != 2) {
        cr_why(why, n, "%s has no size and checksum in info.txt (an older curray wrote it)",
                 name);
        return 0;
    }
    if (st.st_size != rec_size) {
        cr_why(why, n, "%s has %lld bytes, info.txt recorded %lld", name,
                 (long long)st.st_size, rec_size);
        return 0;
    }
    fd = open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    rc = fd < 0 ? -1 : cr_file_sum(fd, &size, &crc);
    if (fd >= 0)
        close(fd);
    if (rc != 0) {
        cr_why(why, n, "%s cannot be read: %s", name, strerror(errno));
        return 0;
    }
    if (size != rec_size || crc != rec_crc) {
        cr_why(why, n, "%s has CRC-32 %08lx, info.txt recorded %08lx", name, crc, rec_crc);
        return 0;
    }
    return 1;
}

int cr_resume_verify(cr_resume *r, const char *dir, const char *types, cr_err *err)
{
    int i, j, dropped = 0;
    r->why[0] = '\0';
    if (!r->body)
        return 0;
    for (i = 0; i < r->n_records; i++) {
        int k = r->order[i], ok = 1;
        char why[sizeof r->why];
        for (const char *t = types; ok == 1 && *t; t++)
            ok = cr_frame_file_matches(r->body[k], dir, *t, k, why, sizeof why);
        if (ok < 0)
            return cr_err_set(err, "--resume: %s; move it away, then run again", why);
        if (ok)
            continue;
        if (dropped++ == 0)
            cr_why(r->why, sizeof r->why, "frame %d: %s", k, why);
        free(r->body[k]);
        r->body[k] = NULL;
    }
    /* the records left, in their order */
    for (i = j = 0; i < r->n_records; i++)
        if (r->body[r->order[i]])
            r->order[j++] = r->order[i];
    r->n_records = j;
    return dropped;
}

void cr_resume_free(cr_resume *r)
{
    if (r->body)
        for (int k = 0; k < r->frames; k++)
            free(r->body[k]);
    free(r->body);
    free(r->order);
    memset(r, 0, sizeof *r);
}
