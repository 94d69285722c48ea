/* Tests of the output side: PNG files, atomic writes, CSV, redshift colours,
 * frame statistics, info.txt, folders and the log. Every test works in its
 * own temporary folder under /tmp, removed afterwards. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <png.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "base/atomic.h"
#include "base/fsutil.h"
#include "output/info.h"
#include "base/log.h"
#include "output/fits.h"
#include "output/output.h"
#include "input/scene.h"
#include "base/png_io.h"
#include "testfs.h"

/* --- helpers -------------------------------------------------------------- */

typedef struct fixture {
    char dir[256];
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    snprintf(f->dir, sizeof f->dir, "/tmp/cr_test_output.XXXXXX");
    if (!mkdtemp(f->dir)) {
        free(f);
        return -1;
    }
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    cr_test_rm_rf(f->dir);
    free(f);
    return 0;
}

static void join(char *out, const fixture *f, const char *name)
{
    assert_int_equal(cr_path_join(out, 4096, f->dir, name), 0);
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Number of entries in dir (without . and ..); *temps counts names that look
 * like our atomic temporaries. */
static int count_entries(const char *dir, int *temps)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    *temps = 0;
    assert_non_null(d);
    while ((e = readdir(d)) != NULL) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        n++;
        if (strstr(e->d_name, ".tmp."))
            (*temps)++;
    }
    closedir(d);
    return n;
}

static char *read_all(const char *path, size_t *len)
{
    FILE *fp = fopen(path, "rb");
    char *buf;
    long n;
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    buf = malloc((size_t)n + 1);
    assert_int_equal(fread(buf, 1, (size_t)n, fp), (size_t)n);
    buf[n] = '\0';
    fclose(fp);
    if (len)
        *len = (size_t)n;
    return buf;
}

/* Fail unless info.txt's text t holds every one of the n lines want[]. */
static void expect_lines(const char *t, const char *const *want, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!strstr(t, want[i]))
            fail_msg("info.txt lacks \"%s\"; it reads:\n%s", want[i], t);
}

static void write_all(const char *path, const void *data, size_t n)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(data, 1, n, fp), n);
    assert_int_equal(fclose(fp), 0);
}

/* Write a PNG of any type with libpng directly. rows: h rows of raw samples
 * (16-bit samples big-endian as PNG stores them). */
static void write_png_raw(const char *path, int w, int h, int color_type, int bit_depth,
                          int interlace, const uint8_t *data, size_t rowbytes,
                          const png_color *palette, int n_palette, const uint8_t *trns,
                          int n_trns)
{
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    png_bytep *rows = malloc((size_t)h * sizeof *rows);
    assert_non_null(fp);
    assert_non_null(png);
    assert_non_null(info);
    if (setjmp(png_jmpbuf(png)))
        fail_msg("libpng failed writing the fixture %s", path);
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, bit_depth, color_type,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (palette)
        png_set_PLTE(png, info, palette, n_palette);
    if (trns)
        png_set_tRNS(png, info, trns, n_trns, NULL);
    for (int y = 0; y < h; y++)
        rows[y] = (png_bytep)(data + (size_t)y * rowbytes);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(rows);
    assert_int_equal(fclose(fp), 0);
}

static uint64_t rng_state = 12345;

static uint32_t rnd(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(rng_state >> 33);
}

/* stdout/stderr capture into a temporary file. */
typedef struct capture {
    int fd, saved;
    char path[4096];
} capture;

static void capture_begin(capture *c, const fixture *f, int fd, const char *name)
{
    FILE *std = fd == STDOUT_FILENO ? stdout : stderr;
    join(c->path, f, name);
    fflush(std);
    c->fd = fd;
    c->saved = dup(fd);
    int t = open(c->path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(c->saved >= 0 && t >= 0);
    dup2(t, fd);
    close(t);
}

static char *capture_end(capture *c)
{
    FILE *std = c->fd == STDOUT_FILENO ? stdout : stderr;
    fflush(std);
    dup2(c->saved, c->fd);
    close(c->saved);
    return read_all(c->path, NULL);
}

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

/* --- PNG ------------------------------------------------------------------ */

static void test_png_roundtrip(void **state)
{
    fixture *f = *state;
    static const int sizes[][2] = {{1, 1}, {3, 7}, {7, 3}, {1, 9}, {64, 33}, {257, 2}};
    char path[4096];
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        int w = sizes[s][0], h = sizes[s][1], rw, rh, temps;
        size_t n = (size_t)w * h * 3;
        uint8_t *img = malloc(n), *back = NULL;
        cr_err err;
        for (size_t i = 0; i < n; i++)
            img[i] = (uint8_t)rnd();
        join(path, f, "rt.png");
        assert_int_equal(cr_png_write(path, w, h, img, &err), 0);
        assert_int_equal(cr_png_read(path, 0, &back, &rw, &rh, &err), 0);
        assert_int_equal(rw, w);
        assert_int_equal(rh, h);
        assert_memory_equal(back, img, n);
        /* the same through every compression level we offer */
        free(back);
        assert_int_equal(cr_png_write_level(path, w, h, img, 9, &err), 0);
        assert_int_equal(cr_png_read(path, (long long)w * h, &back, &rw, &rh, &err), 0);
        assert_memory_equal(back, img, n);
        assert_int_equal(count_entries(f->dir, &temps), 1);
        assert_int_equal(temps, 0);
        free(back);
        free(img);
    }
}

static void test_png_read_grey(void **state)
{
    fixture *f = *state;
    char path[4096];
    uint8_t *rgb;
    int w, h;
    cr_err err;

    /* 8-bit grey */
    static const uint8_t g8[2 * 3] = {0, 50, 100, 150, 200, 255};
    join(path, f, "g8.png");
    write_png_raw(path, 3, 2, PNG_COLOR_TYPE_GRAY, 8, 0, g8, 3, NULL, 0, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    assert_int_equal(w, 3);
    assert_int_equal(h, 2);
    for (int i = 0; i < 6; i++) {
        assert_int_equal(rgb[3 * i], g8[i]);
        assert_int_equal(rgb[3 * i + 1], g8[i]);
        assert_int_equal(rgb[3 * i + 2], g8[i]);
    }
    free(rgb);

    /* 1-bit grey: 0 -> 0, 1 -> 255; bits 1,0,1,1 in one byte */
    static const uint8_t g1[1] = {0xb0};
    join(path, f, "g1.png");
    write_png_raw(path, 4, 1, PNG_COLOR_TYPE_GRAY, 1, 0, g1, 1, NULL, 0, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    static const uint8_t want1[12] = {255, 255, 255, 0, 0, 0, 255, 255, 255, 255, 255, 255};
    assert_memory_equal(rgb, want1, 12);
    free(rgb);

    /* grey + alpha: composited against black, v * a / 255 rounded */
    static const uint8_t ga[4] = {200, 128, 255, 0};
    join(path, f, "ga.png");
    write_png_raw(path, 2, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, 0, ga, 4, NULL, 0, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    assert_int_equal(rgb[0], 100); /* 200 * 128 / 255 = 100.39 */
    assert_int_equal(rgb[1], 100);
    assert_int_equal(rgb[2], 100);
    assert_int_equal(rgb[3], 0);
    free(rgb);

    /* 16-bit grey, interlaced (Adam7), 5 x 5: v16 = 257 * v8 must give v8 */
    uint8_t g16[5 * 10];
    for (int i = 0; i < 25; i++) {
        unsigned v = (unsigned)(i * 10) * 257u;
        g16[2 * i] = (uint8_t)(v >> 8);
        g16[2 * i + 1] = (uint8_t)v;
    }
    join(path, f, "g16i.png");
    write_png_raw(path, 5, 5, PNG_COLOR_TYPE_GRAY, 16, 1, g16, 10, NULL, 0, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    assert_int_equal(w, 5);
    for (int i = 0; i < 25; i++) {
        assert_int_equal(rgb[3 * i], i * 10);
        assert_int_equal(rgb[3 * i + 2], i * 10);
    }
    free(rgb);
}

static void test_png_read_palette(void **state)
{
    fixture *f = *state;
    char path[4096];
    uint8_t *rgb;
    int w, h;
    cr_err err;
    static const png_color pal[3] = {{10, 20, 30}, {200, 100, 50}, {255, 255, 255}};
    /* 4-bit indices 0,1,2,1 */
    static const uint8_t idx[2] = {0x01, 0x21};

    join(path, f, "pal.png");
    write_png_raw(path, 4, 1, PNG_COLOR_TYPE_PALETTE, 4, 0, idx, 2, pal, 3, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    static const uint8_t want[12] = {10, 20, 30, 200, 100, 50, 255, 255, 255, 200, 100, 50};
    assert_memory_equal(rgb, want, 12);
    free(rgb);

    /* with tRNS: entry 1 half transparent, entry 2 fully transparent */
    static const uint8_t trns[3] = {255, 51, 0};
    join(path, f, "palt.png");
    write_png_raw(path, 4, 1, PNG_COLOR_TYPE_PALETTE, 4, 0, idx, 2, pal, 3, trns, 3);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    /* 200*51/255 = 40, 100*51/255 = 20, 50*51/255 = 10 */
    static const uint8_t want_t[12] = {10, 20, 30, 40, 20, 10, 0, 0, 0, 40, 20, 10};
    assert_memory_equal(rgb, want_t, 12);
    free(rgb);
}

static void test_png_read_rgba_16(void **state)
{
    fixture *f = *state;
    char path[4096];
    uint8_t *rgb;
    int w, h;
    cr_err err;

    static const uint8_t rgba[2 * 4] = {255, 128, 0, 255, 100, 200, 50, 64};
    join(path, f, "rgba.png");
    write_png_raw(path, 2, 1, PNG_COLOR_TYPE_RGB_ALPHA, 8, 0, rgba, 8, NULL, 0, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    /* opaque pixel unchanged; alpha 64: 100*64/255 = 25.1, 200*64/255 = 50.2,
     * 50*64/255 = 12.55 -> 13 */
    static const uint8_t want[6] = {255, 128, 0, 25, 50, 13};
    assert_memory_equal(rgb, want, 6);
    free(rgb);

    /* 16-bit RGB: rounded to 8 bits (0x1234 = 4660 -> 4660*255/65535 = 18.13) */
    static const uint8_t rgb16[6] = {0xff, 0xff, 0x00, 0x00, 0x12, 0x34};
    join(path, f, "rgb16.png");
    write_png_raw(path, 1, 1, PNG_COLOR_TYPE_RGB, 16, 0, rgb16, 6, NULL, 0, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    assert_int_equal(rgb[0], 255);
    assert_int_equal(rgb[1], 0);
    assert_int_equal(rgb[2], 18);
    free(rgb);

    /* 16-bit RGBA, interlaced: 50% alpha (0x8000) on white -> 128 */
    static const uint8_t rgba16[8] = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x80, 0x00};
    join(path, f, "rgba16.png");
    write_png_raw(path, 1, 1, PNG_COLOR_TYPE_RGB_ALPHA, 16, 1, rgba16, 8, NULL, 0, NULL, 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), 0);
    assert_int_equal(rgb[0], 128);
    assert_int_equal(rgb[1], 128);
    assert_int_equal(rgb[2], 128);
    free(rgb);
}

static void test_png_read_errors(void **state)
{
    fixture *f = *state;
    char path[4096];
    uint8_t *rgb = (uint8_t *)1;
    int w = 7, h = 7;
    cr_err err;

    /* missing */
    join(path, f, "missing.png");
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), -1);
    assert_null(rgb);
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, "No such file or directory"));

    /* not a PNG */
    join(path, f, "text.png");
    write_all(path, "hello, this is not an image\n", 28);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), -1);
    assert_non_null(strstr(err.msg, "not a PNG file"));
    assert_non_null(strstr(err.msg, path));

    /* empty */
    join(path, f, "empty.png");
    write_all(path, "", 0);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), -1);
    assert_non_null(strstr(err.msg, "not a PNG file"));
    assert_non_null(strstr(err.msg, "empty"));

    /* a folder */
    assert_int_equal(cr_png_read(f->dir, 0, &rgb, &w, &h, &err), -1);
    assert_non_null(strstr(err.msg, f->dir));

    /* truncated: a noisy 64 x 64 image cut in half */
    int n = 64 * 64 * 3;
    uint8_t *img = malloc((size_t)n);
    for (int i = 0; i < n; i++)
        img[i] = (uint8_t)rnd();
    join(path, f, "full.png");
    assert_int_equal(cr_png_write(path, 64, 64, img, &err), 0);
    size_t len;
    char *bytes = read_all(path, &len);
    join(path, f, "half.png");
    write_all(path, bytes, len / 2);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), -1);
    assert_null(rgb);
    assert_non_null(strstr(err.msg, "truncated"));
    assert_non_null(strstr(err.msg, path));

    /* cut inside the header (after the signature) */
    join(path, f, "head.png");
    write_all(path, bytes, 20);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), -1);
    assert_non_null(strstr(err.msg, "truncated"));

    /* corrupt: a byte of the image data flipped -> CRC error from libpng */
    bytes[len / 2] ^= 0x55;
    join(path, f, "corrupt.png");
    write_all(path, bytes, len);
    assert_int_equal(cr_png_read(path, 0, &rgb, &w, &h, &err), -1);
    assert_non_null(strstr(err.msg, "corrupt"));
    assert_non_null(strstr(err.msg, "libpng"));
    free(bytes);
    free(img);
}

static void test_png_max_pixels(void **state)
{
    fixture *f = *state;
    char path[4096];
    uint8_t *rgb, *img = calloc(40 * 30 * 3, 1);
    int w, h;
    cr_err err;

    join(path, f, "40x30.png");
    assert_int_equal(cr_png_write(path, 40, 30, img, &err), 0);
    assert_int_equal(cr_png_read(path, 1199, &rgb, &w, &h, &err), -1);
    assert_null(rgb);
    assert_non_null(strstr(err.msg, "40 x 30 = 1200 pixels (3600 bytes"));
    assert_non_null(strstr(err.msg, "limit of 1199 pixels"));
    assert_int_equal(cr_png_read(path, 1200, &rgb, &w, &h, &err), 0);
    free(rgb);

    /* A 1 x 1 file whose header claims 100000 x 100000: refused from the
     * header alone. Were the 3e10 bytes allocated first, this would fail
     * differently (or exhaust memory under ASan). */
    size_t len;
    join(path, f, "huge.png");
    assert_int_equal(cr_png_write(path, 1, 1, img, &err), 0);
    unsigned char *b = (unsigned char *)read_all(path, &len);
    assert_memory_equal(b + 12, "IHDR", 4);
    for (int k = 0; k < 2; k++) { /* width, height: 100000 big-endian */
        b[16 + 4 * k] = 0;
        b[17 + 4 * k] = 0x01;
        b[18 + 4 * k] = 0x86;
        b[19 + 4 * k] = 0xa0;
    }
    uLong crc = crc32(0L, b + 12, 17);
    b[29] = (unsigned char)(crc >> 24);
    b[30] = (unsigned char)(crc >> 16);
    b[31] = (unsigned char)(crc >> 8);
    b[32] = (unsigned char)crc;
    write_all(path, b, len);
    assert_int_equal(cr_png_read(path, 4096LL * 4096, &rgb, &w, &h, &err), -1);
    assert_non_null(strstr(err.msg, "100000 x 100000 = 10000000000 pixels (30000000000 bytes"));
    free(b);
    free(img);
}

/* --- atomic writes ---------------------------------------------------------- */

static void test_atomic_failures(void **state)
{
    fixture *f = *state;
    char path[4096];
    uint8_t img[3 * 4] = {0};
    cr_err err;
    int temps;

    /* target folder does not exist: a clear message, nothing created */
    join(path, f, "no/such/folder/c_0.png");
    assert_int_equal(cr_png_write(path, 2, 2, img, &err), -1);
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, "No such file or directory"));
    assert_false(exists(path));
    assert_int_equal(count_entries(f->dir, &temps), 0);

    /* a failure between open and commit: the temporary goes, the old file stays */
    join(path, f, "keep.png");
    assert_int_equal(cr_png_write(path, 2, 2, img, &err), 0);
    cr_atomic a;
    assert_int_equal(cr_atomic_open(&a, path, &err), 0);
    assert_true(exists(a.tmp));
    assert_non_null(strstr(a.tmp, "/.keep.png.tmp."));
    fputs("partial", a.fp);
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s", a.tmp);
    cr_atomic_abort(&a);
    assert_false(exists(tmp));
    uint8_t *back;
    int w, h;
    assert_int_equal(cr_png_read(path, 0, &back, &w, &h, &err), 0);
    free(back);

    /* invalid arguments write nothing */
    join(path, f, "bad.png");
    assert_int_equal(cr_png_write(path, 0, 5, img, &err), -1);
    assert_false(exists(path));
    assert_int_equal(count_entries(f->dir, &temps), 1);
    assert_int_equal(temps, 0);
}

static void test_atomic_unwritable_folder(void **state)
{
    fixture *f = *state;
    char sub[4096], path[4200];
    uint8_t img[3] = {1, 2, 3};
    cr_err err;

    if (geteuid() == 0) {
        print_message("SKIPPED test_atomic_unwritable_folder: running as root, folder "
                      "permissions are not enforced (the missing-folder case is tested)\n");
        skip();
    }
    join(sub, f, "ro");
    assert_int_equal(mkdir(sub, 0555), 0);
    snprintf(path, sizeof path, "%s/c_0.png", sub);
    assert_int_equal(cr_png_write(path, 1, 1, img, &err), -1);
    assert_non_null(strstr(err.msg, "Permission denied"));
    assert_false(exists(path));
}

/* Full disk: /dev/full accepts the open and fails every write with ENOSPC. */
static void test_full_disk(void **state)
{
    fixture *f = *state;
    cr_pixel px[64 * 64];
    cr_err err;
    char path[4096], tmp[4096];
    int temps;

    if (!exists("/dev/full")) {
        print_message("SKIPPED test_full_disk: /dev/full does not exist on this system\n");
        skip();
    }
    memset(px, 0, sizeof px);
    for (int i = 0; i < 64 * 64; i++) {
        px[i].outcome = CR_OUT_DISC;
        px[i].redshift = 1.0 / (i + 3);
        px[i].err_mean = 1e-9 * i;
    }
    /* the CSV writer on a stream */
    FILE *fp = fopen("/dev/full", "w");
    assert_non_null(fp);
    assert_int_equal(cr_output_csv_stream(fp, "/dev/full", px, 64, 64, &err), -1);
    assert_string_equal(err.msg, "writing /dev/full: No space left on device");
    fclose(fp);

    /* cr_atomic_commit with its stream on a full disk: error, no temporary,
     * no destination */
    join(path, f, "d_0.csv");
    cr_atomic a;
    assert_int_equal(cr_atomic_open(&a, path, &err), 0);
    snprintf(tmp, sizeof tmp, "%s", a.tmp);
    fclose(a.fp);
    a.fp = fopen("/dev/full", "w");
    assert_non_null(a.fp);
    fputs("x,y\n0,0\n", a.fp);
    assert_int_equal(cr_atomic_commit(&a, &err), -1);
    char want[4200];
    snprintf(want, sizeof want, "writing %s: No space left on device", path);
    assert_string_equal(err.msg, want);
    assert_null(a.fp);
    assert_false(exists(tmp));
    assert_false(exists(path));
    assert_int_equal(count_entries(f->dir, &temps), 0);
}

/* --- redshift colours (6.9.1) -------------------------------------------- */

static cr_rgb rs(int outcome, double z)
{
    cr_pixel p;
    memset(&p, 0, sizeof p);
    p.outcome = (uint8_t)outcome;
    p.redshift = z;
    return cr_redshift_color(&p);
}

#define assert_rgb(c, R, G, B)                                                                   \
    do {                                                                                         \
        cr_rgb c_ = (c);                                                                         \
        assert_int_equal(c_.r, R);                                                               \
        assert_int_equal(c_.g, G);                                                               \
        assert_int_equal(c_.b, B);                                                               \
    } while (0)

static void test_redshift_color(void **state)
{
    (void)state;
    /* B = 255 atan(z) 2/pi, R = 255 - B before rounding; rounded to nearest
     * with halves away from zero. Hand values:
     *   z = 0:       B = 0                        -> (255, 0, 0)
     *   z = 1:       B = 127.5 exactly, R = 127.5 -> (128, 0, 128) (both halves round up)
     *   z = tan(pi/8): B = 63.75, R = 191.25      -> (191, 0, 64)
     *   z = 3:       B = 202.7676, R = 52.2324    -> (52, 0, 203)
     *   z = 0.5:     B = 75.2676, R = 179.7324    -> (180, 0, 75)
     *   z = 0.1:     B = 16.1800, R = 238.8200    -> (239, 0, 16)
     *   z = inf:     B = 255                      -> (0, 0, 255) */
    assert_rgb(rs(CR_OUT_DISC, 0.0), 255, 0, 0);
    assert_rgb(rs(CR_OUT_DISC, 1.0), 128, 0, 128);
    assert_rgb(rs(CR_OUT_SPHERE, 1.0), 128, 0, 128);
    assert_rgb(rs(CR_OUT_DISC, tan(CR_PI / 8)), 191, 0, 64);
    assert_rgb(rs(CR_OUT_DISC, 3.0), 52, 0, 203);
    assert_rgb(rs(CR_OUT_SPHERE, 0.5), 180, 0, 75);
    assert_rgb(rs(CR_OUT_DISC, 0.1), 239, 0, 16);
    assert_rgb(rs(CR_OUT_DISC, INFINITY), 0, 0, 255);
    assert_rgb(rs(CR_OUT_DISC, 1e300), 0, 0, 255);
    /* the horizon: z = 0, red, whatever is stored */
    assert_rgb(rs(CR_OUT_HORIZON, 0.0), 255, 0, 0);
    assert_rgb(rs(CR_OUT_HORIZON, -1.0), 255, 0, 0);
    /* source inside the ergosphere: green */
    assert_rgb(rs(CR_OUT_DISC, -1.0), 0, 255, 0);
    assert_rgb(rs(CR_OUT_SPHERE, -1.0), 0, 255, 0);
    /* no source: black */
    assert_rgb(rs(CR_OUT_SKY, 1.0), 0, 0, 0);
    assert_rgb(rs(CR_OUT_SKY, -1.0), 0, 0, 0);
    assert_rgb(rs(CR_OUT_ERROR, 1.0), 0, 0, 0);
    assert_rgb(rs(CR_OUT_LIMIT, 1.0), 0, 0, 0);
    assert_rgb(rs(CR_OUT_NONE, 1.0), 0, 0, 0);
    assert_rgb(rs(CR_OUT_DISC, NAN), 0, 0, 0);

    /* redshift_sky: the sky by its own ratio, same hand values; everything
     * else as above */
    {
        cr_pixel p;
        memset(&p, 0, sizeof p);
        p.outcome = CR_OUT_SKY;
        p.redshift = 1.0;
        assert_rgb(cr_redshift_sky_color(&p), 128, 0, 128);
        p.redshift = 3.0;
        assert_rgb(cr_redshift_sky_color(&p), 52, 0, 203);
        p.redshift = 0.1;
        assert_rgb(cr_redshift_sky_color(&p), 239, 0, 16);
        p.redshift = -1.0; /* undefined */
        assert_rgb(cr_redshift_sky_color(&p), 0, 0, 0);
        p.redshift = NAN;
        assert_rgb(cr_redshift_sky_color(&p), 0, 0, 0);
        for (int o = 0; o < CR_OUT_COUNT_; o++)
            for (int k = 0; k < 4; k++) {
                static const double zs[] = {-1.0, 0.0, 0.5, 3.0};
                cr_rgb a, b;
                if (o == CR_OUT_SKY)
                    continue;
                p.outcome = (uint8_t)o;
                p.redshift = zs[k];
                a = cr_redshift_sky_color(&p);
                b = cr_redshift_color(&p);
                assert_true(a.r == b.r && a.g == b.g && a.b == b.b);
            }
    }
}

/* --- frame files ------------------------------------------------------------ */

static void make_frame(cr_pixel *px, int w, int h)
{
    static const double special[] = {-1.0, 0.0, 1.0, 0.1, 1.0 / 3.0, 1e-300, 5e-324,
                                     1.7976931348623157e308, 123456789.123456789};
    for (int i = 0; i < w * h; i++) {
        cr_pixel *p = &px[i];
        memset(p, 0, sizeof *p);
        p->outcome = (uint8_t)(1 + i % 6);
        p->color.r = (uint8_t)rnd();
        p->color.g = (uint8_t)rnd();
        p->color.b = (uint8_t)rnd();
        p->steps = rnd() % 100000u;
        p->object = -1;
        if (i % 3 == 0)
            p->redshift = special[i % 9];
        else
            p->redshift = (double)rnd() / (double)rnd();
        p->err_mean = ldexp((double)rnd(), -40 - (int)(rnd() % 40));
        p->err_std = i % 5 == 0 ? 0.0 : ldexp((double)rnd(), -50);
        /* hit point: set on every pixel; written only for disc and sphere */
        p->hit_r = i % 7 == 0 ? special[i % 9] : 2.0 + (double)rnd() / (double)rnd();
        p->hit_phi = i % 11 == 0 ? 0.0 : CR_TWO_PI * ((double)rnd() / 4294967296.0);
        /* the counts: -1 (no ray traced to an end), 0, small and the cap */
        p->order = (int16_t)(i % 13 == 0 ? -1 : i % 13 == 1 ? CR_COUNT_MAX : (int)(rnd() % 5));
        p->theta_turns = (int16_t)(i % 17 == 0 ? -1 : (int)(rnd() % 7));
        p->delay = i % 13 == 0 ? -1.0 : 100.0 * ((double)rnd() / 4294967296.0) - 30.0;
    }
}

static void test_csv_roundtrip(void **state)
{
    fixture *f = *state;
    enum { W = 13, H = 11 };
    cr_pixel px[W * H];
    char path[4096], line[512];
    cr_err err;
    int temps;

    make_frame(px, W, H);
    px[5].outcome = CR_OUT_ERROR; /* defined as -1 for error/limit pixels */
    px[5].redshift = 0.25;
    px[6].outcome = CR_OUT_DISC;
    px[6].redshift = NAN;
    assert_int_equal(cr_output_csv(f->dir, 4, px, W, H, &err), 0);
    join(path, f, "d_4.csv");
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    assert_non_null(fgets(line, sizeof line, fp));
    assert_string_equal(line,
                        "x,y,r,g,b,steps,redshift,err_mean,err_std,outcome,hit_r,hit_phi,"
                        "bolometric,order,theta_turns,delay\n");
    for (int i = 0; i < W * H; i++) {
        int x, y, n_hit = 0;
        unsigned r, g, b, steps;
        double z, em, es, hr, hp;
        char name[32], counts[64];
        assert_non_null(fgets(line, sizeof line, fp));
        assert_int_equal(sscanf(line, "%d,%d,%u,%u,%u,%u,%lf,%lf,%lf,%31[a-z],%lf,%lf%n", &x, &y,
                                &r, &g, &b, &steps, &z, &em, &es, name, &hr, &hp, &n_hit),
                         12);
        /* then the bolometric column: -1 except on a Keplerian disc or a
         * moving sphere hit */
        if (!((px[i].outcome == CR_OUT_DISC || px[i].outcome == CR_OUT_SPHERE) &&
              px[i].bolo >= 0.0))
            assert_memory_equal(line + n_hit, ",-1,", 4);
        /* the counts, as the pixel holds them, then the delay: nan except on a
         * disc or sphere hit, where it reads back exactly */
        {
            char *last = strrchr(line, ',');
            assert_non_null(last);
            if (px[i].outcome == CR_OUT_DISC || px[i].outcome == CR_OUT_SPHERE)
                assert_true(strtod(last + 1, NULL) == px[i].delay);
            else
                assert_string_equal(last, ",nan\n");
            last[0] = '\n';
            last[1] = '\0';
        }
        snprintf(counts, sizeof counts, ",%d,%d\n", px[i].order, px[i].theta_turns);
        assert_true(strlen(line) > strlen(counts));
        assert_string_equal(line + strlen(line) - strlen(counts), counts);
        if (px[i].outcome == CR_OUT_DISC || px[i].outcome == CR_OUT_SPHERE) {
            assert_true(hr == px[i].hit_r); /* exact: the shortest form reads back */
            assert_true(hp == px[i].hit_phi);
        } else {
            assert_true(hr == -1.0 && hp == -1.0);
        }
        assert_int_equal(x, i % W);
        assert_int_equal(y, i / W);
        assert_int_equal(r, px[i].color.r);
        assert_int_equal(g, px[i].color.g);
        assert_int_equal(b, px[i].color.b);
        assert_int_equal(steps, px[i].steps);
        if (i == 5 || i == 6 || px[i].outcome == CR_OUT_ERROR || px[i].outcome == CR_OUT_LIMIT)
            assert_true(z == -1.0);
        else
            assert_true(z == px[i].redshift); /* exact: the shortest form reads back */
        assert_true(em == px[i].err_mean);
        assert_true(es == px[i].err_std);
        assert_string_equal(name, cr_outcome_name(px[i].outcome));
    }
    assert_null(fgets(line, sizeof line, fp));
    fclose(fp);
    assert_int_equal(count_entries(f->dir, &temps), 1);
    assert_int_equal(temps, 0);
}

/* The CSV's numbers in their shortest form that reads back exactly: 0.1,
 * not %.17g's 0.10000000000000001 (shortest.h). */
static void test_csv_shortest(void **state)
{
    fixture *f = *state;
    cr_pixel px[2];
    char path[4096], *t;
    cr_err err;
    memset(px, 0, sizeof px);
    px[0].outcome = CR_OUT_DISC;
    px[0].redshift = 0.1;
    px[0].err_mean = 1e-5;
    px[0].err_std = 2.0 / 3.0;
    px[0].hit_r = 6.02214076e23;
    px[0].hit_phi = 5e-324;
    px[0].bolo = 0.3;
    px[0].steps = 17;
    px[0].order = 2;
    px[0].theta_turns = 1;
    px[0].delay = -1.0; /* a delay may be -1: only nan means none */
    px[1].order = -1;
    px[1].outcome = CR_OUT_SKY;
    px[1].redshift = -0.0;
    px[1].err_mean = 123456789012345678.0;
    px[1].err_std = 1e16;
    assert_int_equal(cr_output_csv(f->dir, 0, px, 2, 1, &err), 0);
    join(path, f, "d_0.csv");
    t = read_all(path, NULL);
    assert_string_equal(t, "x,y,r,g,b,steps,redshift,err_mean,err_std,outcome,hit_r,hit_phi,"
                           "bolometric,order,theta_turns,delay\n"
                           "0,0,0,0,0,17,0.1,1e-05,0.6666666666666666,disc,6.02214076e+23,"
                           "5e-324,0.3,2,1,-1\n"
                           "1,0,0,0,0,0,-0,1.2345678901234568e+17,10000000000000000,sky,-1,-1,"
                           "-1,-1,0,nan\n");
    free(t);
}

/* The w x h PNG name in the fixture's folder holds colour(px[i]) at pixel i
 * (colour NULL: px[i].color). */
static void assert_png_is(const fixture *f, const char *name, const cr_pixel *px, int w, int h,
                          cr_rgb (*colour)(const cr_pixel *))
{
    char path[4096];
    uint8_t *rgb;
    int pw, ph;
    cr_err err;
    join(path, f, name);
    assert_int_equal(cr_png_read(path, 0, &rgb, &pw, &ph, &err), 0);
    assert_int_equal(pw, w);
    assert_int_equal(ph, h);
    for (int i = 0; i < w * h; i++) {
        cr_rgb c = colour ? colour(&px[i]) : px[i].color;
        assert_rgb(((cr_rgb){rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]}), c.r, c.g, c.b);
    }
    free(rgb);
}

static void test_frame_pngs(void **state)
{
    fixture *f = *state;
    enum { W = 5, H = 3 };
    cr_pixel px[W * H];
    cr_err err;

    make_frame(px, W, H);
    assert_int_equal(cr_output_color_png(f->dir, 3, px, W, H, &err), 0);
    assert_int_equal(cr_output_redshift_png(f->dir, 3, px, W, H, 0, &err), 0);
    assert_png_is(f, "c_3.png", px, W, H, NULL);
    assert_png_is(f, "r_3.png", px, W, H, cr_redshift_color);
    /* redshift_sky: the sky pixels (outcome 4) coloured by their ratio */
    assert_int_equal(cr_output_redshift_png(f->dir, 4, px, W, H, 1, &err), 0);
    assert_png_is(f, "r_4.png", px, W, H, cr_redshift_sky_color);

    /* n_<k>.png: the colour of each hit's image order, black elsewhere */
    {
        static const struct {
            uint8_t outcome;
            int order;
            cr_rgb c;
        } want[] = {{CR_OUT_DISC, 0, {255, 176, 64}},   {CR_OUT_DISC, 1, {64, 160, 255}},
                    {CR_OUT_SPHERE, 2, {96, 255, 96}},  {CR_OUT_DISC, 3, {255, 64, 255}},
                    {CR_OUT_DISC, 4, {255, 255, 255}},  {CR_OUT_DISC, 900, {255, 255, 255}},
                    {CR_OUT_SKY, 1, {0, 0, 0}},         {CR_OUT_HORIZON, 2, {0, 0, 0}},
                    {CR_OUT_DISC, -1, {0, 0, 0}}};
        cr_frame fr;
        cr_frame_output o;
        memset(&fr, 0, sizeof fr);
        fr.width = W;
        fr.height = H;
        memset(&o, 0, sizeof o);
        o.dir = f->dir;
        o.k = 5;
        o.frame = &fr;
        o.px = px;
        for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
            cr_rgb c;
            px[i].outcome = want[i].outcome;
            px[i].order = (int16_t)want[i].order;
            c = cr_order_color(&px[i]);
            assert_int_equal(c.r, want[i].c.r);
            assert_int_equal(c.g, want[i].c.g);
            assert_int_equal(c.b, want[i].c.b);
        }
        assert_int_equal(cr_output_write_order(&o, &err), 0);
        assert_png_is(f, "n_5.png", px, W, H, cr_order_color);
    }

    /* missing output folder: the message names the file */
    char missing[4096];
    join(missing, f, "nope");
    assert_int_equal(cr_output_csv(missing, 0, px, W, H, &err), -1);
    assert_non_null(strstr(err.msg, "nope/d_0.csv"));
    assert_int_equal(cr_output_color_png(missing, 0, px, W, H, &err), -1);
    assert_non_null(strstr(err.msg, "nope/c_0.png"));
}

/* --- statistics and info.txt -------------------------------------------- */

static void test_stats(void **state)
{
    (void)state;
    cr_pixel px[10];
    cr_frame_stats st;
    static const int outcomes[10] = {1, 1, 2, 3, 4, 4, 4, 5, 6, 0};
    memset(px, 0, sizeof px);
    for (int i = 0; i < 10; i++) {
        px[i].outcome = (uint8_t)outcomes[i];
        px[i].steps = (uint32_t)(100 * (i + 1));
        px[i].err_mean = 1e-10 * (i + 1);
    }
    px[7].err_mean = NAN; /* a failed ray: left out of the error figures */
    cr_frame_stats_compute(px, 10, 2.5, &st);
    assert_true(st.seconds == 2.5);
    assert_int_equal(st.rays, 9); /* the CR_OUT_NONE pixel was not traced */
    assert_int_equal(st.steps, 100ull * (1 + 2 + 3 + 4 + 5 + 6 + 7 + 8 + 9));
    assert_int_equal(st.max_steps_ray, 900);
    assert_int_equal(st.counts[CR_OUT_NONE], 1);
    assert_int_equal(st.counts[CR_OUT_HORIZON], 2);
    assert_int_equal(st.counts[CR_OUT_DISC], 1);
    assert_int_equal(st.counts[CR_OUT_SPHERE], 1);
    assert_int_equal(st.counts[CR_OUT_SKY], 3);
    assert_int_equal(st.counts[CR_OUT_ERROR], 1);
    assert_int_equal(st.counts[CR_OUT_LIMIT], 1);
    /* mean of 1..7 and 9 (x 1e-10) = 37/8 */
    assert_true(fabs(st.err_mean - 37.0 / 8.0 * 1e-10) < 1e-22);
    assert_true(st.err_max == 9e-10);

    cr_frame_stats_compute(px, 0, 0.0, &st);
    assert_int_equal(st.rays, 0);
    assert_true(st.err_mean == 0.0);

    assert_string_equal(cr_outcome_name(CR_OUT_NONE), "none");
    assert_string_equal(cr_outcome_name(CR_OUT_HORIZON), "horizon");
    assert_string_equal(cr_outcome_name(CR_OUT_DISC), "disc");
    assert_string_equal(cr_outcome_name(CR_OUT_SPHERE), "sphere");
    assert_string_equal(cr_outcome_name(CR_OUT_SKY), "sky");
    assert_string_equal(cr_outcome_name(CR_OUT_ERROR), "error");
    assert_string_equal(cr_outcome_name(CR_OUT_LIMIT), "limit");
    assert_string_equal(cr_outcome_name(CR_OUT_OUTSIDE), "outside");
    assert_string_equal(cr_outcome_name(99), "unknown");

    /* a fisheye pixel outside the image circle: counted, but not a ray; the
     * CSV's (and FITS's, Python's) values are all undefined */
    {
        cr_pixel q[2];
        cr_pixel_values v;
        cr_rgb c;
        memset(q, 0, sizeof q);
        q[0].outcome = CR_OUT_SKY;
        q[0].steps = 7;
        q[1].outcome = CR_OUT_OUTSIDE;
        q[1].redshift = q[1].hit_r = q[1].hit_phi = q[1].bolo = -1.0;
        cr_frame_stats_compute(q, 2, 1.0, &st);
        assert_int_equal(st.rays, 1);
        assert_int_equal(st.steps, 7);
        assert_int_equal(st.counts[CR_OUT_OUTSIDE], 1);
        q[1].redshift = 0.5; /* whatever it holds, the CSV says undefined */
        v = cr_pixel_csv_values(&q[1]);
        assert_true(v.redshift == -1.0 && v.hit_r == -1.0 && v.hit_phi == -1.0 &&
                    v.bolometric == -1.0 && v.delay != v.delay);
        c = cr_redshift_color(&q[1]);
        assert_true(c.r == 0 && c.g == 0 && c.b == 0);
    }
}

static void test_info(void **state)
{
    fixture *f = *state;
    cr_scene s;
    cr_scene_sphere sp[2];
    cr_sysconfig cfg;
    cr_frame_stats st[2];
    cr_pixel px[4];
    cr_err err;
    char path[4096];
    int temps;

    memset(&s, 0, sizeof s);
    memset(sp, 0, sizeof sp);
    memset(&cfg, 0, sizeof cfg);
    s.path = "scenes/demo.yml";
    s.m = (cr_anim){1, 1};
    s.a = (cr_anim){0, 0.9};
    s.q = (cr_anim){0, 0};
    s.obs_r = (cr_anim){30, 20};
    s.obs_theta = (cr_anim){CR_PI / 2, CR_PI / 2};
    s.obs_phi = (cr_anim){0, CR_PI};
    s.hfov = (cr_anim){CR_PI / 4, CR_PI / 4};
    s.has_disc = 1;
    s.disc_color1 = (cr_rgb){255, 128, 0};
    s.disc_color2 = (cr_rgb){0, 127, 255};
    s.disc_n_radial = 4;
    s.disc_n_sectors = 16;
    s.disc_r_in = (cr_anim){6, 6};
    s.disc_r_out = (cr_anim){15, 15};
    s.has_sky = 1;
    s.sky_image = "scenes/sky_stars.png";
    s.sky_width = 2048;
    s.sky_height = 1024;
    s.sky_boundary = (cr_anim){100, 100};
    sp[0].color = (cr_rgb){10, 20, 30};
    sp[0].n_lat = 8;
    sp[0].n_lon = 16;
    sp[0].r = (cr_anim){10, 10};
    sp[0].theta = (cr_anim){CR_PI / 3, CR_PI / 3};
    sp[0].radius = (cr_anim){1.5, 2.5};
    sp[0].line = 12;
    sp[1].line = 20;
    s.spheres = sp;
    s.n_spheres = 2;
    s.horizon_color = (cr_rgb){255, 0, 0};
    s.error_color = (cr_rgb){0, 0, 255};
    cfg.gpu_enabled[0] = 1;
    cfg.gpu_enabled[2] = 1;
    cfg.cpu_threads = 0;
    cfg.raytracer.horizon_epsilon = 0.005;
    cfg.raytracer.integrator = CR_INTEG_MINO;
    cfg.raytracer.tolerance = 1e-8;
    cfg.raytracer.step_multiplier = 0.03125;
    cfg.raytracer.max_steps = 100000;
    cfg.raytracer.max_turns = 4;
    cfg.auto_accept = 1;

    memset(px, 0, sizeof px);
    px[0].outcome = CR_OUT_HORIZON;
    px[1].outcome = CR_OUT_SKY;
    px[2].outcome = CR_OUT_SKY;
    px[3].outcome = CR_OUT_DISC;
    for (int i = 0; i < 4; i++)
        px[i].steps = 50;
    cr_frame_stats_compute(px, 4, 0.5, &st[0]);
    cr_frame_stats_compute(px, 4, 0.25, &st[1]);
    st[0].frame = 0;
    st[1].frame = 1;

    cr_run_info run = {"scenes/demo.yml", NULL, "cpu", 640, 480, 3, "icrd", "9.8.7",
                       NULL, NULL, NULL, NULL, NULL};
    assert_int_equal(cr_info_write(f->dir, &run, &s, &cfg, st, 2, &err), 0);
    join(path, f, "info.txt");
    char *t = read_all(path, NULL);
    static const char *const want[] = {
        "curray 9.8.7",
        "Started ",
        "  scene file             scenes/demo.yml\n",
        "  configuration file     (built-in defaults)\n",
        "  backend                cpu\n",
        "  frame size             640 x 480 pixels\n",
        "  frames                 3\n",
        "  output types           icrd\n",
        "  mass M                 1\n",
        "  spin a = J/M           0 -> 0.9\n",
        "  r                      30 -> 20\n",
        "  theta                  90 deg\n",
        "  phi                    0 -> 180 deg\n",
        "  horizontal fov         45 deg\n",
        "  vertical fov           from the horizontal fov",
        "  colour 1 (top)         [255, 128, 0]\n",
        "  colour 2 (bottom)      [0, 127, 255]\n",
        "  radial rings           4\n",
        "  sectors                16\n",
        "  inner radius           6\n",
        "  image                  scenes/sky_stars.png\n",
        "  image size             2048 x 1024 pixels\n",
        "  boundary R             100\n",
        "Spheres: 2\n",
        "Sphere 0 (line 12)\n",
        "  colour                 [10, 20, 30]\n",
        "  latitude bands         8\n",
        "  theta                  60 deg\n",
        "  radius                 1.5 -> 2.5\n",
        "Sphere 1 (line 20)\n",
        "  horizon                [255, 0, 0]\n",
        "  GPUs enabled           0, 2\n",
        "  CPU threads            all online cores\n",
        "  horizon epsilon        0.005\n",
        "  integrator             mino\n",
        "  tolerance              1e-08\n",
        "  step multiplier        0.03125 (rk4 only, unused)\n",
        "  max steps per ray      100000\n",
        "  auto accept            yes\n",
        "Frame 0\n",
        "  wall time              0.500 s\n",
        "  rays                   4\n",
        "  integrator steps       200\n",
        "  steps per ray          50.0 (max 50)\n",
        "  rays per second        8\n",
        "Frame 1\n",
        "  rays per second        16\n",
        "  pixels                 horizon 1, disc 1, sphere 0, sky 2, error 0, limit 0\n",
        "Finished 2 of 3 frames (run incomplete)\n",
    };
    expect_lines(t, want, sizeof want / sizeof want[0]);
    assert_null(strstr(t, "Frame 2"));
    free(t);

    /* rewritten after the last frame; no scene or config is fine too */
    run.frames = 2;
    assert_int_equal(cr_info_write(f->dir, &run, NULL, NULL, st, 2, &err), 0);
    t = read_all(path, NULL);
    assert_non_null(strstr(t, "Finished 2 of 2 frames\n"));
    free(t);

    /* fisheye pixels outside the image circle get their own count, only when
     * there are some */
    st[1].counts[CR_OUT_OUTSIDE] = 5;
    assert_int_equal(cr_info_write(f->dir, &run, NULL, NULL, st, 2, &err), 0);
    t = read_all(path, NULL);
    assert_non_null(
        strstr(t, "pixels                 horizon 1, disc 1, sphere 0, sky 2, error 0, limit 0, "
                  "outside the image 5\n"));
    free(t);
    assert_int_equal(count_entries(f->dir, &temps), 1);
    assert_int_equal(temps, 0);
}

/* The table of output types: every letter accepted in one place, every other
 * byte refused with the message -t gives, the implied types, the per-frame
 * files' names and order, and each per-frame row's writer writing the file
 * its name says. */
static void test_output_types(void **state)
{
    fixture *f = *state;
    static const char *const list = "use any of i, c, r, d, b, n, s, l, f, v";
    cr_err err;
    char want[256], one[2] = {0, 0}, bad[3] = {'c', 0, 0}, out[16], path[4096];
    int n = cr_output_type_count(), frames = 0;

    assert_int_equal(n, 10);
    for (int i = 0; i < n; i++) {
        const cr_output_type *t = cr_output_type_at(i);
        assert_ptr_equal(cr_output_type_find(t->letter), t);
        assert_true((t->scope == CR_OUTPUT_PER_FRAME) == (t->write != NULL));
        one[0] = t->letter;
        cr_err why = {""};
        if (t->letter == 'f') /* a build with cfitsio writes FITS (its module loads) */
            assert_int_equal(t->available(&why), CR_TEST_HAVE_FITS);
        if (t->available && !t->available(&why)) {
            assert_int_equal(cr_output_types_check(one, &err), -1);
            assert_string_equal(err.msg, why.msg[0] ? why.msg : t->unavailable);
        } else {
            assert_int_equal(cr_output_types_check(one, &err), 0);
        }
        frames += t->scope == CR_OUTPUT_PER_FRAME;
    }
    assert_int_equal(frames, 8);
    assert_null(cr_output_type_at(n));
    assert_null(cr_output_type_at(-1));
    for (int c = 1; c < 256; c++) {
        if (cr_output_type_find((char)c))
            continue;
        bad[1] = (char)c;
        assert_int_equal(cr_output_types_check(bad, &err), -1);
        snprintf(want, sizeof want, "-t: unknown output type '%c' in '%s'; %s", c, bad, list);
        assert_string_equal(err.msg, want);
    }
    assert_int_equal(cr_output_types_check("", &err), -1);
    snprintf(want, sizeof want, "-t: empty output type; %s", list);
    assert_string_equal(err.msg, want);

    assert_true(cr_output_types_has("v", 'c'));
    assert_true(cr_output_types_has("icr", 'r'));
    assert_false(cr_output_types_has("icr", 'd'));
    assert_false(cr_output_types_has("icr", '\0'));
    cr_output_frame_letters("vdi", out, sizeof out);
    assert_string_equal(out, "cd");
    cr_output_frame_letters("fbdrcfcv", out, sizeof out);
    assert_string_equal(out, "crdbf");
    cr_output_frame_letters("fnc", out, sizeof out);
    assert_string_equal(out, "cnf");
    cr_output_frame_letters("iv", out, sizeof out);
    assert_string_equal(out, "c");
    cr_output_frame_letters("i", out, sizeof out);
    assert_string_equal(out, "");
    cr_output_frame_letters("crdbf", out, 3);
    assert_string_equal(out, "cr");

    assert_int_equal(cr_output_file_name('c', 3, out, sizeof out), 0);
    assert_string_equal(out, "c_3.png");
    assert_int_equal(cr_output_file_name('d', 0, out, sizeof out), 0);
    assert_string_equal(out, "d_0.csv");
    assert_int_equal(cr_output_file_name('f', 12, out, sizeof out), 0);
    assert_string_equal(out, "f_12.fits");
    assert_int_equal(cr_output_file_name('b', 7, out, sizeof out), 0);
    assert_string_equal(out, "b_7.png");
    assert_int_equal(cr_output_file_name('i', 0, out, sizeof out), -1);
    assert_int_equal(cr_output_file_name('v', 0, out, sizeof out), -1);
    assert_int_equal(cr_output_file_name('z', 0, out, sizeof out), -1);
    assert_int_equal(cr_output_file_name('c', 123456, out, 8), -1);

    /* each per-frame writer, through its row, writes the file of its name */
    {
        cr_scene s;
        cr_frame fr;
        cr_pixel px[6 * 4];
        memset(&s, 0, sizeof s);
        s.path = "types.yml";
        s.m = (cr_anim){1, 1};
        s.obs_r = (cr_anim){30, 30};
        s.obs_theta = (cr_anim){CR_PI / 2, CR_PI / 2};
        s.hfov = (cr_anim){CR_PI / 4, CR_PI / 4};
        assert_int_equal(cr_scene_frame(&s, 0, 1, 6, 4, NULL, &fr, NULL, &err), 0);
        memset(px, 0, sizeof px);
        for (int i = 0; i < 6 * 4; i++)
            px[i].outcome = CR_OUT_SKY;
        cr_frame_output o = {f->dir, 2, 3, &fr, px, &s, NULL, 0};
        for (int i = 0; i < n; i++) {
            const cr_output_type *t = cr_output_type_at(i);
            if (t->scope != CR_OUTPUT_PER_FRAME || (t->available && !t->available(NULL)))
                continue;
            assert_int_equal(cr_output_file_name(t->letter, 2, out, sizeof out), 0);
            join(path, f, out);
            assert_int_equal(access(path, F_OK), -1);
            if (t->letter == 's') {
                /* the spectrum needs a Keplerian disc: refused, nothing written */
                assert_int_equal(t->write(&o, &err), -1);
                assert_string_equal(err.msg, "-t s: the frame has no Keplerian disc");
                assert_int_equal(access(path, F_OK), -1);
                continue;
            }
            assert_int_equal(t->write(&o, &err), 0);
            assert_int_equal(access(path, F_OK), 0);
        }
    }
}

/* The FITS file's layout read from its headers (2880-byte blocks of 80-byte
 * cards): the HDUs, the bytes a pixel over the image extensions (|BITPIX|/8
 * of each 2-d image), and the header blocks of the largest header. Returns
 * the file's size in bytes (0: not a FITS file as expected). */
static long fits_layout(const char *path, int w, int h, int *hdus, int *pixel_bytes,
                        int *max_blocks)
{
    size_t n = 0;
    char *t = read_all(path, &n);
    size_t at = 0;
    *hdus = *pixel_bytes = *max_blocks = 0;
    while (t && at + 2880 <= n) {
        long bitpix = 0, naxis = -1, nax[2] = {0, 0};
        int end = 0, blocks = 0;
        while (!end && at + 2880 <= n) {
            for (int c = 0; c < 36; c++) {
                const char *card = t + at + 80 * (size_t)c;
                if (!strncmp(card, "END     ", 8))
                    end = 1;
                else if (!strncmp(card, "BITPIX  =", 9))
                    bitpix = strtol(card + 10, NULL, 10);
                else if (!strncmp(card, "NAXIS   =", 9))
                    naxis = strtol(card + 10, NULL, 10);
                else if (!strncmp(card, "NAXIS1  =", 9))
                    nax[0] = strtol(card + 10, NULL, 10);
                else if (!strncmp(card, "NAXIS2  =", 9))
                    nax[1] = strtol(card + 10, NULL, 10);
            }
            at += 2880;
            blocks++;
        }
        if (!end || bitpix == 0 || naxis < 0) {
            free(t);
            return 0;
        }
        (*hdus)++;
        if (blocks > *max_blocks)
            *max_blocks = blocks;
        if (naxis == 2) {
            size_t data = (size_t)labs(bitpix) / 8 * (size_t)nax[0] * (size_t)nax[1];
            assert_int_equal(nax[0], w);
            assert_int_equal(nax[1], h);
            *pixel_bytes += (int)(labs(bitpix) / 8);
            at += (data + 2879) / 2880 * 2880;
        }
    }
    free(t);
    return at == n ? (long)n : 0;
}

/* The memory check's count of a FITS frame (cr_fits_memory) against the file
 * the writer makes: the same bytes a pixel and HDUs, each HDU's headers
 * within the blocks allowed, and the whole file within the count. */
static void test_fits_memory(void **state)
{
    fixture *f = *state;
    const int w = 7, h = 5;
    cr_scene s;
    cr_frame fr;
    cr_pixel px[7 * 5];
    cr_err err;
    char path[4096];
    int hdus, ppx, blocks;
    long size;
    double per_pixel, headers;

    if (!CR_TEST_HAVE_FITS) {
        print_message("SKIPPED: this build writes no FITS\n");
        return;
    }
    memset(&s, 0, sizeof s);
    s.path = "fits.yml";
    s.m = (cr_anim){1, 1};
    s.obs_r = (cr_anim){30, 30};
    s.obs_theta = (cr_anim){CR_PI / 2, CR_PI / 2};
    s.hfov = (cr_anim){CR_PI / 4, CR_PI / 4};
    assert_int_equal(cr_scene_frame(&s, 0, 1, w, h, NULL, &fr, NULL, &err), 0);
    memset(px, 0, sizeof px);
    for (int i = 0; i < w * h; i++)
        px[i].outcome = CR_OUT_SKY;
    assert_int_equal(cr_output_fits(f->dir, 0, 1, &s, &fr, px, &err), 0);
    join(path, f, "f_0.fits");
    size = fits_layout(path, w, h, &hdus, &ppx, &blocks);
    assert_true(size > 0);
    /* the count's figure a pixel: what one more row of pixels adds */
    per_pixel = (cr_fits_memory(w, 2 * h) - cr_fits_memory(w, h)) / (double)(w * h);
    headers = cr_fits_memory(w, h) - per_pixel * w * h - 8.0 * w;
    print_message("FITS: %d HDUs, %d bytes a pixel in the file; counted %.17g a pixel, "
                  "%.17g bytes of headers\n", hdus, ppx, per_pixel, headers);
    assert_true(per_pixel == (double)ppx);
    assert_int_equal(cr_fits_pixel_bytes(), ppx);
    assert_int_equal(cr_fits_hdus(), hdus);
    assert_true(blocks <= 4);
    assert_true(headers == (double)hdus * 4.0 * 2880.0);
    assert_true((double)size <= cr_fits_memory(w, h));
}

/* The first and last frame of a run of n frames of s, as the run passes
 * them to info.txt (fr[0], fr[1]). */
static void info_ends(const cr_scene *s, int n, cr_frame fr[2], cr_run_info *run)
{
    cr_err err;
    memset(run, 0, sizeof *run);
    run->frames = n;
    assert_int_equal(cr_scene_frame(s, 0, n, 64, 48, NULL, &fr[0], NULL, &err), 0);
    assert_int_equal(cr_scene_frame(s, n - 1, n, 64, 48, NULL, &fr[1], NULL, &err), 0);
    run->first = &fr[0];
    run->last = &fr[1];
}

/* info.txt of a Keplerian disc: model, sense, ISCO in M and in the scene's
 * units, effective inner radius, peak temperature, from the run's first and
 * last frame; none of the chessboard's lines. M = 2, a = 0 then 1.8 (a/M =
 * 0.9): r_isco = 6 M then BPT's prograde 2.3208830 M (4.641766 in the
 * scene's units). */
static void test_info_keplerian(void **state)
{
    fixture *f = *state;
    cr_scene s;
    cr_sysconfig cfg;
    cr_run_info run;
    cr_frame fr[2];
    cr_err err;
    char path[4096];
    char *t;

    memset(&s, 0, sizeof s);
    s.path = "kep.yml";
    s.m = (cr_anim){2, 2};
    s.a = (cr_anim){0, 1.8};
    s.obs_r = (cr_anim){100, 100};
    s.obs_theta = (cr_anim){CR_PI / 2, CR_PI / 2};
    s.hfov = (cr_anim){CR_PI / 4, CR_PI / 4};
    s.has_disc = 1;
    s.disc_model = CR_DISC_KEPLERIAN;
    s.disc_r_in = (cr_anim){8, 8};
    s.disc_r_out = (cr_anim){60, 60};
    s.disc_has_r_in = 1;
    s.disc_temperature = 12000;
    cr_sysconfig_defaults(&cfg);
    info_ends(&s, 5, fr, &run);
    assert_int_equal(cr_info_write(f->dir, &run, &s, &cfg, NULL, 0, &err), 0);
    join(path, f, "info.txt");
    t = read_all(path, NULL);
    static const char *const want[] = {
        "Accretion disc\n  model                  keplerian\n",
        "  orbit sense            prograde (counter-clockwise about +z)\n",
        "  inner radius           8\n",
        "  outer radius           60\n",
        "  r_isco                 6 -> 2.320883042 M (12 -> 4.641766084 in the scene's units)\n",
        "  effective inner radius 6 -> 4 M (12 -> 8 in the scene's units)\n",
        "  peak temperature       12000 K\n",
    };
    expect_lines(t, want, sizeof want / sizeof want[0]);
    assert_null(strstr(t, "radial rings"));
    assert_null(strstr(t, "colour 1"));
    free(t);
    /* one frame: the values of the frame traced (a = 0), not of the
       animation's end */
    info_ends(&s, 1, fr, &run);
    assert_int_equal(cr_info_write(f->dir, &run, &s, &cfg, NULL, 0, &err), 0);
    t = read_all(path, NULL);
    static const char *const want1[] = {
        "  r_isco                 6 M (12 in the scene's units)\n",
        "  effective inner radius 6 M (12 in the scene's units)\n",
        "  frames                 1\n  animation              " CR_INFO_ONE_FRAME_OF_ANIMATION "\n",
        "  spin a = J/M           0 -> 1.8\n",
    };
    expect_lines(t, want1, sizeof want1 / sizeof want1[0]);
    free(t);
    /* the same scene in 5 frames: start to end, no such line */
    info_ends(&s, 5, fr, &run);
    assert_int_equal(cr_info_write(f->dir, &run, &s, &cfg, NULL, 0, &err), 0);
    t = read_all(path, NULL);
    assert_null(strstr(t, "animation "));
    free(t);
    /* without frames, the lines derived per frame are left out */
    assert_int_equal(cr_info_write(f->dir, NULL, &s, &cfg, NULL, 0, &err), 0);
    t = read_all(path, NULL);
    assert_non_null(strstr(t, "  orbit sense            prograde\n"));
    assert_null(strstr(t, "r_isco"));
    assert_null(strstr(t, "effective inner radius"));
    free(t);
    /* retrograde, inner radius omitted: the ISCO; nothing animated, one
       frame: no animation line */
    s.a = (cr_anim){1.8, 1.8};
    s.disc_retrograde = 1;
    s.disc_has_r_in = 0;
    info_ends(&s, 1, fr, &run);
    assert_int_equal(cr_info_write(f->dir, &run, &s, &cfg, NULL, 0, &err), 0);
    t = read_all(path, NULL);
    assert_null(strstr(t, "animation "));
    static const char *const want2[] = {
        "  orbit sense            retrograde (clockwise about +z)\n",
        "  inner radius           the ISCO\n",
        "  r_isco                 8.71735228 M (17.43470456 in the scene's units)\n",
        "  effective inner radius 8.71735228 M (17.43470456 in the scene's units)\n",
    };
    expect_lines(t, want2, sizeof want2 / sizeof want2[0]);
    free(t);
}

/* info.txt of an observer at infinity, a sky at infinity and rk4 */
static void test_info_at_infinity(void **state)
{
    fixture *f = *state;
    cr_scene s;
    cr_sysconfig cfg;
    cr_err err;
    char path[4096];
    char *t;

    memset(&s, 0, sizeof s);
    s.path = "inf.yml";
    s.m = (cr_anim){1, 1};
    s.a = (cr_anim){0.9, 0.9};
    s.obs_at_infinity = 1;
    s.obs_r = (cr_anim){INFINITY, INFINITY};
    s.obs_theta = (cr_anim){CR_PI / 2, CR_PI / 2};
    s.hextent = (cr_anim){40, 20};
    s.has_sky = 1;
    s.sky_image = "sky.png";
    s.sky_width = 4;
    s.sky_height = 2;
    s.sky_at_infinity = 1;
    cr_sysconfig_defaults(&cfg);
    cfg.raytracer.integrator = CR_INTEG_RK4;
    assert_int_equal(cr_info_write(f->dir, NULL, &s, &cfg, NULL, 0, &err), 0);
    join(path, f, "info.txt");
    t = read_all(path, NULL);
    static const char *const want[] = {
        "  r                      inf (the observer at infinity)\n",
        "  image plane width      40 -> 20 M\n",
        "  image plane height     from the width and the aspect ratio\n",
        "  boundary R             inf (the sky at infinity)\n",
        "  integrator             rk4\n",
        "  tolerance              1e-07 (mino only, unused)\n",
        "  step multiplier        0.03125\n",
    };
    expect_lines(t, want, sizeof want / sizeof want[0]);
    assert_null(strstr(t, "fov"));
    free(t);
    s.has_vextent = 1;
    s.vextent = (cr_anim){30, 30};
    assert_int_equal(cr_info_write(f->dir, NULL, &s, &cfg, NULL, 0, &err), 0);
    t = read_all(path, NULL);
    assert_non_null(strstr(t, "  image plane height     30 M\n"));
    free(t);
}

/* Bytes this process has handed to write(2) and its kin so far, as the
 * kernel counts them ("wchar" in /proc/self/io); -1 where it does not. */
static long long wchar_now(void)
{
    FILE *fp = fopen("/proc/self/io", "r");
    char line[128];
    long long v = -1;
    if (!fp)
        return -1;
    while (fgets(line, sizeof line, fp))
        if (sscanf(line, "wchar: %lld", &v) == 1)
            break;
    fclose(fp);
    return v;
}

static int ends_with(const char *s, size_t len, const char *tail)
{
    size_t n = strlen(tail);
    return len >= n && memcmp(s + len - n, tail, n) == 0;
}

/* The text after the "Started" line (the only line that depends on when the
 * file was begun). */
static const char *after_started(const char *t)
{
    const char *p = strstr(t, "\nStarted ");
    assert_non_null(p);
    p = strchr(p + 1, '\n');
    assert_non_null(p);
    return p;
}

/* A run of 1,000 frames through cr_info: after every frame info.txt is the
 * file after the previous frame plus exactly this frame's record, which ends
 * with "Finished k+1 of N frames"; no temporary is left; and the bytes
 * written for a frame (counted by the appender and, where the kernel counts
 * them, by /proc/self/io) are that record alone, so they do not grow with
 * the frame number while the file grows to ~300 KB. At the end the file is
 * the one cr_info_write writes in one go for the same frames. */
static void test_info_appends(void **state)
{
    fixture *f = *state;
    enum { N = 1000 };
    cr_frame_stats *st = calloc(N, sizeof *st);
    cr_pixel px[4];
    cr_info info;
    cr_err err;
    char path[4096], want[128], *prev = NULL;
    size_t prev_len = 0, first_rec = 0, max_rec = 0;
    int temps, kernel_counts = wchar_now() >= 0;
    cr_run_info run = {"scenes/demo.yml", NULL, "cpu", 1, 1, N, "i", "9.8.7", NULL, NULL, NULL, NULL, NULL};
    cr_sysconfig cfg;

    assert_non_null(st);
    cr_sysconfig_defaults(&cfg);
    memset(px, 0, sizeof px);
    for (int i = 0; i < 4; i++) {
        px[i].outcome = (uint8_t)(i < 2 ? CR_OUT_SKY : CR_OUT_DISC);
        px[i].steps = 40u + (uint32_t)i;
    }
    join(path, f, "info.txt");
    assert_int_equal(cr_info_begin(&info, f->dir, &run, NULL, &cfg, &err), 0);
    assert_false(exists(path)); /* nothing until a frame has finished */

    for (int k = 0; k < N; k++) {
        unsigned long long b0 = info.file.bytes_written;
        long long w0, w1;
        size_t len, rec_len;
        char *t;

        cr_frame_stats_compute(px, 4, 0.125 * (1 + k % 5), &st[k]);
        st[k].frame = k;
        w0 = wchar_now();
        assert_int_equal(cr_info_add_frame(&info, &st[k], &err), 0);
        w1 = wchar_now();
        assert_int_equal(info.n_done, k + 1);

        t = read_all(path, &len);
        assert_true(len > prev_len);
        if (prev)
            assert_memory_equal(t, prev, prev_len);
        rec_len = len - prev_len;
        if (k == 0) { /* the header, a blank line, the first record */
            assert_non_null(strstr(t, "\n\nFrame 0\n"));
        } else {
            snprintf(want, sizeof want, "Frame %d\n", k);
            assert_memory_equal(t + prev_len, want, strlen(want));
        }
        snprintf(want, sizeof want, "Finished %d of %d frames%s\n\n", k + 1, N,
                 k + 1 < N ? " (run incomplete)" : "");
        if (!ends_with(t, len, want))
            fail_msg("after frame %d info.txt does not end with \"%s\"", k, want);
        /* one frame in the record */
        assert_null(strstr(k ? t + prev_len : strstr(t, "\nFrame ") + 1, "\nFrame "));

        assert_int_equal(info.file.bytes_written - b0, rec_len);
        if (kernel_counts)
            assert_int_equal(w1 - w0, (long long)rec_len);
        if (k == 1)
            first_rec = rec_len;
        if (rec_len > max_rec && k >= 1)
            max_rec = rec_len;
        assert_int_equal(count_entries(f->dir, &temps), 1);
        assert_int_equal(temps, 0);
        free(prev);
        prev = t;
        prev_len = len;
    }
    assert_int_equal(cr_info_end(&info, &err), 0);
    /* the longest record is the first one plus the digits that "Frame 999"
     * and "Finished 1000 of" add, whatever the size of the file */
    assert_true(prev_len > 200u * first_rec);
    assert_true(max_rec <= first_rec + 8);

    {
        char dir2[4096], path2[4096];
        char *t2;
        join(dir2, f, "oneshot");
        assert_int_equal(cr_mkdir_p(dir2, &err), 0);
        assert_int_equal(cr_info_write(dir2, &run, NULL, &cfg, st, N, &err), 0);
        assert_int_equal(cr_path_join(path2, sizeof path2, dir2, "info.txt"), 0);
        t2 = read_all(path2, NULL);
        assert_string_equal(after_started(prev), after_started(t2));
        free(t2);
    }
    free(prev);
    free(st);
}

/* A record that does not fit (here: the file size limit, as on a full disk)
 * leaves info.txt exactly as it was, and the next record goes on from there. */
/* --resume's part of info.txt: the run hash, stale files and a resumed run's Started/Resumed
 * lines in the header; cr_info_resume writes the kept records in their
 * order with "Finished" counted again, and the next record continues the
 * count. */
static void test_info_resume(void **state)
{
    fixture *f = *state;
    cr_run_info run = {"s.yml", NULL, "cpu", 2, 1, 4, "i", "9.8.7",
                       "0123456789abcdef", "c_<k>.png for k = 4-7", "2026-01-02 03:04:05 +0000", NULL, NULL};
    char *bodies[4] = {NULL, "Frame 1\n  rays 2\n", NULL, "Frame 3\n  rays 2\n"};
    int order[2] = {3, 1};
    cr_frame_stats st;
    cr_pixel px[2];
    cr_sysconfig cfg;
    cr_info info;
    cr_err err;
    char path[4096], *t;
    size_t len;

    cr_sysconfig_defaults(&cfg);
    memset(px, 0, sizeof px);
    join(path, f, "info.txt");
    assert_int_equal(cr_info_begin(&info, f->dir, &run, NULL, &cfg, &err), 0);
    assert_int_equal(cr_info_resume(&info, bodies, order, 0, &err), 0);
    assert_false(exists(path)); /* nothing kept: nothing written yet */
    assert_int_equal(cr_info_resume(&info, bodies, order, 2, &err), 0);
    assert_int_equal(info.n_done, 2);
    cr_frame_stats_compute(px, 2, 0.5, &st);
    st.frame = 0;
    assert_int_equal(cr_info_add_frame(&info, &st, &err), 0);
    assert_int_equal(cr_info_end(&info, &err), 0);
    t = read_all(path, &len);
    assert_non_null(strstr(t, "\nStarted                  2026-01-02 03:04:05 +0000\nResumed  "));
    assert_non_null(strstr(t, "\n  run hash               0123456789abcdef\n"));
    assert_non_null(strstr(t, "\n  stale files            c_<k>.png for k = 4-7 (from an earlier "
                              "run; not overwritten, not deleted)\n"));
    assert_non_null(strstr(t, "\nFrame 3\n  rays 2\nFinished 1 of 4 frames (run incomplete)\n\n"
                              "Frame 1\n  rays 2\nFinished 2 of 4 frames (run incomplete)\n\n"
                              "Frame 0\n"));
    assert_non_null(strstr(t, "Finished 3 of 4 frames (run incomplete)\n\n"));
    free(t);
}

static void test_info_append_fails(void **state)
{
    fixture *f = *state;
    cr_frame_stats st;
    cr_pixel px[2];
    cr_info info;
    cr_err err;
    char path[4096], *before, *t;
    size_t before_len, len;
    struct rlimit old, lim;
    cr_run_info run = {"scenes/demo.yml", NULL, "cpu", 2, 1, 5, "i", "9.8.7", NULL, NULL, NULL, NULL, NULL};

    memset(px, 0, sizeof px);
    px[0].outcome = CR_OUT_HORIZON;
    px[1].outcome = CR_OUT_SKY;
    cr_frame_stats_compute(px, 2, 1.0, &st);
    join(path, f, "info.txt");

    /* no frame finished: no file */
    assert_int_equal(cr_info_begin(&info, f->dir, &run, NULL, NULL, &err), 0);
    assert_int_equal(cr_info_end(&info, &err), 0);
    assert_false(exists(path));

    assert_int_equal(cr_info_begin(&info, f->dir, &run, NULL, NULL, &err), 0);
    for (int k = 0; k < 2; k++) {
        st.frame = k;
        assert_int_equal(cr_info_add_frame(&info, &st, &err), 0);
    }
    before = read_all(path, &before_len);

    /* room for 10 more bytes: the write is cut short, then refused */
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    lim = old;
    lim.rlim_cur = (rlim_t)before_len + 10;
    signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
    st.frame = 2;
    assert_int_equal(cr_info_add_frame(&info, &st, &err), -1);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, SIG_DFL);
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, strerror(EFBIG)));
    assert_int_equal(info.n_done, 2);
    t = read_all(path, &len);
    assert_int_equal(len, before_len);
    assert_memory_equal(t, before, len);
    free(t);

    /* the next try appends after the last whole record */
    assert_int_equal(cr_info_add_frame(&info, &st, &err), 0);
    assert_int_equal(cr_info_end(&info, &err), 0);
    t = read_all(path, &len);
    assert_memory_equal(t, before, before_len);
    assert_non_null(strstr(t + before_len, "Frame 2\n"));
    assert_true(ends_with(t, len, "Finished 3 of 5 frames (run incomplete)\n\n"));
    free(t);
    free(before);
}

/* --- folders ------------------------------------------------------------------ */

static void test_mkdir_p(void **state)
{
    fixture *f = *state;
    char path[4096], file[4096];
    struct stat st;
    cr_err err;

    join(path, f, "a/b/c/d");
    assert_int_equal(cr_mkdir_p(path, &err), 0);
    assert_int_equal(stat(path, &st), 0);
    assert_true(S_ISDIR(st.st_mode));
    assert_int_equal(cr_mkdir_p(path, &err), 0); /* exists: fine */
    join(path, f, "a//b/e/");
    assert_int_equal(cr_mkdir_p(path, &err), 0);
    join(path, f, "a/b/e");
    assert_true(exists(path));
    assert_int_equal(cr_mkdir_p("/", &err), 0);
    assert_int_equal(cr_mkdir_p(".", &err), 0);

    /* a file in the way, as the folder itself and as a parent */
    join(file, f, "file");
    write_all(file, "x", 1);
    assert_int_equal(cr_mkdir_p(file, &err), -1);
    assert_non_null(strstr(err.msg, "exists and is not a folder"));
    assert_non_null(strstr(err.msg, file));
    join(path, f, "file/sub/deeper");
    assert_int_equal(cr_mkdir_p(path, &err), -1);
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, "exists and is not a folder"));
    assert_false(exists(path));

    assert_int_equal(cr_mkdir_p("", &err), -1);
    assert_non_null(strstr(err.msg, "empty"));

    /* a place no one can create a folder in */
    assert_int_equal(cr_mkdir_p("/proc/cr_test_cannot_exist/x", &err), -1);
    assert_non_null(strstr(err.msg, "/proc/cr_test_cannot_exist"));
}

static void test_path_join(void **state)
{
    (void)state;
    char out[16];
    assert_int_equal(cr_path_join(out, sizeof out, "out", "c_0.png"), 0);
    assert_string_equal(out, "out/c_0.png");
    assert_int_equal(cr_path_join(out, sizeof out, "out/", "c_0.png"), 0);
    assert_string_equal(out, "out/c_0.png");
    assert_int_equal(cr_path_join(out, sizeof out, "", "c_0.png"), 0);
    assert_string_equal(out, "c_0.png");
    assert_int_equal(cr_path_join(out, sizeof out, "out", "/abs"), 0);
    assert_string_equal(out, "/abs");
    assert_int_equal(cr_path_join(out, sizeof out, "a_long_folder", "name.txt"), -1);
    assert_string_equal(out, "");
}

/* --- log -------------------------------------------------------------------------- */

static void test_log(void **state)
{
    fixture *f = *state;
    char dir[4096];
    cr_log lg;
    cr_err err;
    capture co, ce;
    char *out, *errs, *file;

    /* quiet: nothing on stdout; the file gets info and error (no detail
     * without verbose); errors still reach stderr */
    join(dir, f, "logs/deeper");
    assert_int_equal(cr_log_open(&lg, dir, 0, 0, 1, &err), 0);
    assert_non_null(strstr(lg.path, "logs/deeper/curray.log"));
    capture_begin(&co, f, STDOUT_FILENO, "out1.txt");
    capture_begin(&ce, f, STDERR_FILENO, "err1.txt");
    cr_log_info(&lg, "hello %d", 42);
    cr_log_detail(&lg, "detail %s", "hidden");
    cr_log_progress(&lg, "frame 0: %5.1f%%", 50.0);
    cr_log_error(&lg, "bad thing: %s", "oops");
    errs = capture_end(&ce);
    out = capture_end(&co);
    assert_string_equal(out, "");
    assert_string_equal(errs, "bad thing: oops\n");
    cr_log_close(&lg);
    file = read_all(lg.path, NULL);
    assert_int_equal(count_lines(file), 2);
    assert_non_null(strstr(file, "[info] hello 42\n"));
    assert_non_null(strstr(file, "[error] bad thing: oops\n"));
    assert_null(strstr(file, "hidden"));
    assert_null(strstr(file, "frame 0"));
    /* "YYYY-mm-dd HH:MM:SS.mmm [" */
    assert_true(strlen(file) > 24 && file[4] == '-' && file[10] == ' ' && file[19] == '.' &&
                file[23] == ' ' && file[24] == '[');
    free(out);
    free(errs);
    free(file);

    /* verbose, not quiet: console and file get info and detail; the file is
     * overwritten; a multi-line message gets one stamp per line */
    assert_int_equal(cr_log_open(&lg, dir, 0, 1, 0, &err), 0);
    capture_begin(&co, f, STDOUT_FILENO, "out2.txt");
    cr_log_info(&lg, "line one\nline two\n");
    cr_log_detail(&lg, "detail %s", "shown");
    out = capture_end(&co);
    cr_log_close(&lg);
    assert_string_equal(out, "line one\nline two\ndetail shown\n");
    file = read_all(lg.path, NULL);
    assert_int_equal(count_lines(file), 3);
    assert_non_null(strstr(file, "[info] line one\n"));
    assert_non_null(strstr(file, "[info] line two\n"));
    assert_non_null(strstr(file, "[detail] detail shown\n"));
    assert_null(strstr(file, "hello"));
    free(out);
    free(file);

    /* progress to a non-terminal: at most one line per 10 %, per frame */
    assert_int_equal(cr_log_open(&lg, dir, 0, 0, 0, &err), 0);
    capture_begin(&co, f, STDOUT_FILENO, "out3.txt");
    for (int frame = 0; frame < 2; frame++)
        for (int i = 0; i <= 1000; i++)
            cr_log_progress(&lg, "frame %d: %5.1f%% done", frame, i / 10.0);
    out = capture_end(&co);
    cr_log_close(&lg);
    assert_int_equal(count_lines(out), 22); /* 0, 10, ..., 100 for each frame */
    assert_non_null(strstr(out, "frame 0:   0.0% done\nframe 0:  10.0% done\n"));
    assert_non_null(strstr(out, "frame 1: 100.0% done\n"));
    file = read_all(lg.path, NULL);
    assert_string_equal(file, ""); /* progress is not logged */
    free(out);
    free(file);

    /* two frames in flight, their progress interleaved: each is followed on
     * its own, so still one line per 10 % and frame */
    assert_int_equal(cr_log_open(&lg, dir, 0, 0, 0, &err), 0);
    capture_begin(&co, f, STDOUT_FILENO, "out3b.txt");
    for (int i = 0; i <= 100; i++) {
        cr_log_progress(&lg, "frame 1/2: %3d%%", i);
        cr_log_progress(&lg, "frame 2/2: %3d%%", i / 2);
        cr_log_progress(&lg, "frame 2/2: starting"); /* no %: at most every 5 s */
    }
    out = capture_end(&co);
    cr_log_close(&lg);
    assert_int_equal(count_lines(out), 11 + 6 + 1);
    assert_non_null(strstr(out, "frame 1/2: 100%\n"));
    assert_non_null(strstr(out, "frame 2/2:  50%\n"));
    assert_non_null(strstr(out, "frame 2/2: starting\n"));
    free(out);

    /* keep_log: a new file named after the time and pid */
    assert_int_equal(cr_log_open(&lg, dir, 1, 0, 1, &err), 0);
    char suffix[64];
    snprintf(suffix, sizeof suffix, "-%ld.log", (long)getpid());
    assert_non_null(strstr(lg.path, "/curray-"));
    assert_non_null(strstr(lg.path, suffix));
    cr_log_info(&lg, "kept");
    cr_log_close(&lg);
    file = read_all(lg.path, NULL);
    assert_non_null(strstr(file, "[info] kept\n"));
    free(file);

    /* the log folder cannot be made: an error, the console still works */
    char blocker[4096];
    join(blocker, f, "blocker");
    write_all(blocker, "x", 1);
    assert_int_equal(cr_log_open(&lg, blocker, 0, 0, 0, &err), -1);
    assert_non_null(strstr(err.msg, "exists and is not a folder"));
    assert_null(lg.file);
    capture_begin(&co, f, STDOUT_FILENO, "out4.txt");
    cr_log_info(&lg, "still here");
    cr_log_info(NULL, "no log at all");
    out = capture_end(&co);
    cr_log_close(&lg);
    assert_string_equal(out, "still here\nno log at all\n");
    free(out);
}

/* Several threads logging at once: every line arrives whole. */
typedef struct log_job {
    cr_log *lg;
    int id;
} log_job;

static void *log_thread(void *arg)
{
    log_job *job = arg;
    for (int i = 0; i < 500; i++) {
        cr_log_info(job->lg, "thread line %d of 500 with some padding text", i);
        cr_log_progress(job->lg, "frame %d: %d%%", job->id, i / 5);
    }
    return NULL;
}

static void test_log_threads(void **state)
{
    fixture *f = *state;
    char dir[4096];
    pthread_t tid[4];
    log_job jobs[4];
    cr_log lg;
    cr_err err;
    capture co;

    join(dir, f, "logs");
    assert_int_equal(cr_log_open(&lg, dir, 0, 0, 0, &err), 0);
    capture_begin(&co, f, STDOUT_FILENO, "out.txt");
    for (int t = 0; t < 4; t++) {
        jobs[t].lg = &lg;
        jobs[t].id = t;
        assert_int_equal(pthread_create(&tid[t], NULL, log_thread, &jobs[t]), 0);
    }
    for (int t = 0; t < 4; t++)
        pthread_join(tid[t], NULL);
    char *out = capture_end(&co);
    cr_log_close(&lg);
    char *file = read_all(lg.path, NULL);
    assert_int_equal(count_lines(file), 2000);
    for (char *p = file; *p; p = strchr(p, '\n') + 1)
        assert_int_equal(strncmp(p + 23, " [info] thread line ", 20), 0);
    /* console: the 2000 info lines whole, plus one progress line per 10 %
     * (0 % .. 90 %) and thread */
    int n = count_lines(out), info = 0;
    for (char *p = out; *p; p = strchr(p, '\n') + 1)
        info += strncmp(p, "thread line ", 12) == 0;
    assert_int_equal(info, 2000);
    assert_int_equal(n - info, 4 * 10);
    free(out);
    free(file);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_png_roundtrip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_read_grey, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_read_palette, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_read_rgba_16, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_read_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_max_pixels, setup, teardown),
        cmocka_unit_test_setup_teardown(test_atomic_failures, setup, teardown),
        cmocka_unit_test_setup_teardown(test_atomic_unwritable_folder, setup, teardown),
        cmocka_unit_test_setup_teardown(test_full_disk, setup, teardown),
        cmocka_unit_test(test_redshift_color),
        cmocka_unit_test_setup_teardown(test_csv_roundtrip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_frame_pngs, setup, teardown),
        cmocka_unit_test(test_stats),
        cmocka_unit_test_setup_teardown(test_info, setup, teardown),
        cmocka_unit_test_setup_teardown(test_info_keplerian, setup, teardown),
        cmocka_unit_test_setup_teardown(test_output_types, setup, teardown),
        cmocka_unit_test_setup_teardown(test_csv_shortest, setup, teardown),
        cmocka_unit_test_setup_teardown(test_info_at_infinity, setup, teardown),
        cmocka_unit_test_setup_teardown(test_info_appends, setup, teardown),
        cmocka_unit_test_setup_teardown(test_info_append_fails, setup, teardown),
        cmocka_unit_test_setup_teardown(test_info_resume, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mkdir_p, setup, teardown),
        cmocka_unit_test(test_path_join),
        cmocka_unit_test_setup_teardown(test_fits_memory, setup, teardown),
        cmocka_unit_test_setup_teardown(test_log, setup, teardown),
        cmocka_unit_test_setup_teardown(test_log_threads, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
