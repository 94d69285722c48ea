/* curray io: PNG files through libpng (png_io.h).
 *
 * libpng reports errors by longjmp to the setjmp in png_jmpbuf(). Our error
 * handler stores libpng's message in a cr_png_ctx (never printing it), and
 * the warning handler only keeps the last warning. The cr_png_ctx lives in
 * the caller of the function that calls setjmp, and the locals of that
 * function that change after setjmp and are read after the longjmp are
 * volatile (C11 7.13.2.1). */
#include "png_io.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "atomic.h"
#include "memcheck.h"

/* What the callbacks of one read or write leave behind. */
typedef struct cr_png_ctx {
    FILE *fp;
    char msg[512];     /* libpng's error, or our I/O error */
    char warning[256]; /* last warning, kept only for the curious */
} cr_png_ctx;

static void cr_png_error_fn(png_structp png, png_const_charp msg)
{
    cr_png_ctx *ctx = (cr_png_ctx *)png_get_error_ptr(png);
    /* Keep a message already set by our I/O callbacks: it is more precise. */
    if (ctx && !ctx->msg[0])
        snprintf(ctx->msg, sizeof ctx->msg, "invalid or corrupt PNG data (libpng: %s)",
                 msg ? msg : "unknown error");
    png_longjmp(png, 1);
}

static void cr_png_warning_fn(png_structp png, png_const_charp msg)
{
    cr_png_ctx *ctx = (cr_png_ctx *)png_get_error_ptr(png);
    if (ctx)
        snprintf(ctx->warning, sizeof ctx->warning, "%s", msg ? msg : "");
}

static void cr_png_write_fn(png_structp png, png_bytep data, size_t len)
{
    cr_png_ctx *ctx = (cr_png_ctx *)png_get_io_ptr(png);
    if (fwrite(data, 1, len, ctx->fp) != len) {
        snprintf(ctx->msg, sizeof ctx->msg, "%s", strerror(errno));
        png_error(png, "write error");
    }
}

static void cr_png_flush_fn(png_structp png)
{
    cr_png_ctx *ctx = (cr_png_ctx *)png_get_io_ptr(png);
    if (fflush(ctx->fp) != 0) {
        snprintf(ctx->msg, sizeof ctx->msg, "%s", strerror(errno));
        png_error(png, "write error");
    }
}

static void cr_png_read_fn(png_structp png, png_bytep data, size_t len)
{
    cr_png_ctx *ctx = (cr_png_ctx *)png_get_io_ptr(png);
    if (fread(data, 1, len, ctx->fp) != len) {
        if (ferror(ctx->fp))
            snprintf(ctx->msg, sizeof ctx->msg, "read error: %s", strerror(errno));
        else
            snprintf(ctx->msg, sizeof ctx->msg, "the file is truncated (it ends too early)");
        png_error(png, "read error");
    }
}

/* Encode w x h RGB rows into ctx->fp. The setjmp lives here and ctx in the
 * caller, so nothing libpng's callbacks change is a local of this function;
 * png and info are not changed between setjmp and a longjmp. */
static int cr_png_encode(cr_png_ctx *ctx, const char *path, int w, int h, png_bytep *rows,
                         int level, cr_err *err)
{
    png_structp png;
    png_infop info = NULL;

    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, ctx, cr_png_error_fn,
                                  cr_png_warning_fn);
    if (png)
        info = png_create_info_struct(png);
    if (!png || !info) {
        cr_err_set(err, "cannot write PNG '%s': out of memory", path);
        goto fail;
    }
    if (setjmp(png_jmpbuf(png))) {
        cr_err_set(err, "cannot write PNG '%s': %s", path, ctx->msg);
        goto fail;
    }
    png_set_write_fn(png, ctx, cr_png_write_fn, cr_png_flush_fn);
    png_set_compression_level(png, level);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return 0;

fail:
    png_destroy_write_struct(&png, &info);
    return -1;
}

int cr_png_write_level(const char *path, int w, int h, const uint8_t *rgb, int level,
                       cr_err *err)
{
    cr_atomic a;
    cr_png_ctx ctx;
    png_bytep *rows;

    if (w <= 0 || h <= 0 || (long long)w * h > 0x7fffffffLL / 3)
        return cr_err_set(err, "cannot write PNG '%s': invalid size %d x %d", path, w, h);
    if (!rgb)
        return cr_err_set(err, "cannot write PNG '%s': no pixel data", path);
    if (level < 0 || level > 9)
        level = 6;

    rows = malloc((size_t)h * sizeof *rows);
    if (!rows)
        return cr_err_set(err, "cannot write PNG '%s': out of memory", path);
    for (int y = 0; y < h; y++)
        rows[y] = (png_bytep)(rgb + (size_t)y * (size_t)w * 3);

    if (cr_atomic_open(&a, path, err) != 0) {
        free(rows);
        return -1;
    }
    memset(&ctx, 0, sizeof ctx);
    ctx.fp = a.fp;
    if (cr_png_encode(&ctx, path, w, h, rows, level, err) != 0) {
        cr_atomic_abort(&a);
        free(rows);
        return -1;
    }
    free(rows);
    return cr_atomic_commit(&a, err);
}

int cr_png_write(const char *path, int w, int h, const uint8_t *rgb, cr_err *err)
{
    return cr_png_write_level(path, w, h, rgb, 6, err);
}

/* The refusal of an image larger than max_pixels, naming its size. */
static int cr_png_too_large(cr_err *err, const char *path, unsigned long w, unsigned long h,
                            long long max_pixels)
{
    unsigned long long px = (unsigned long long)w * h;
    return cr_err_set(err,
                      "cannot read PNG '%s': the image is %lu x %lu = %llu pixels (%llu bytes as "
                      "8-bit RGB), more than the limit of %lld pixels",
                      path, w, h, px, px * 3ull, max_pixels);
}

/* Decode after the signature check: ctx->fp is positioned after 8 bytes.
 * As for writing, ctx belongs to the caller, away from the setjmp. */
static int cr_png_read_body(cr_png_ctx *ctx, const char *path, long long max_pixels,
                            uint8_t **rgb, int *wout, int *hout, cr_err *err)
{
    png_structp png = NULL;
    png_infop info = NULL;
    /* Assigned after setjmp and freed on the longjmp path: volatile. */
    uint8_t *volatile buf = NULL;
    png_bytep *volatile rows = NULL;
    png_uint_32 w, h;
    int bit_depth, color_type, interlace, channels;
    size_t rowbytes, need;

    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, ctx, cr_png_error_fn,
                                 cr_png_warning_fn);
    if (png)
        info = png_create_info_struct(png);
    if (!png || !info) {
        cr_err_set(err, "cannot read PNG '%s': out of memory", path);
        goto fail;
    }
    if (setjmp(png_jmpbuf(png))) {
        cr_err_set(err, "cannot read PNG '%s': %s", path, ctx->msg);
        goto fail;
    }
    png_set_read_fn(png, ctx, cr_png_read_fn);
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    png_get_IHDR(png, info, &w, &h, &bit_depth, &color_type, &interlace, NULL, NULL);

    /* The size check comes before any allocation of pixel memory. */
    if (max_pixels > 0 && (unsigned long long)w * h > (unsigned long long)max_pixels) {
        cr_png_too_large(err, path, (unsigned long)w, (unsigned long)h, max_pixels);
        goto fail;
    }
    if (w > 0x7fffffffu || h > 0x7fffffffu) {
        cr_err_set(err, "cannot read PNG '%s': the image is too large", path);
        goto fail;
    }

    /* Everything to 8-bit RGB or RGBA (alpha composited below). */
    png_set_expand(png); /* palette -> RGB, grey < 8 bit -> 8 bit, tRNS -> alpha */
#ifdef PNG_READ_SCALE_16_TO_8_SUPPORTED
    png_set_scale_16(png); /* 16 -> 8 bit, rounded: v8 = round(v16 * 255 / 65535) */
#else
    png_set_strip_16(png);
#endif
    if (!(color_type & PNG_COLOR_MASK_COLOR))
        png_set_gray_to_rgb(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);

    channels = png_get_channels(png, info);
    rowbytes = png_get_rowbytes(png, info);
    if ((channels != 3 && channels != 4) || png_get_bit_depth(png, info) != 8 ||
        rowbytes != (size_t)w * (size_t)channels) {
        cr_err_set(err, "cannot read PNG '%s': unsupported pixel layout (%d channels)", path,
                   channels);
        goto fail;
    }
    need = rowbytes * (size_t)h;
    if (need / rowbytes != (size_t)h) {
        cr_err_set(err, "cannot read PNG '%s': the image is too large", path);
        goto fail;
    }
    {
        cr_err mem;
        struct stat fst;
        double bytes = (double)need + (double)h * sizeof(png_bytep);
        if (cr_mem_check(bytes, &mem)) {
            cr_err_set(err, "cannot read PNG '%s': its %lu x %lu pixels (%zu bytes decoded) %s",
                       path, (unsigned long)w, (unsigned long)h, need, mem.msg);
            goto fail;
        }
        /* a limited read (a sky image) refuses a decompression bomb: more
         * than CR_PNG_MAX_RATIO times its file's size and above
         * CR_PNG_BOMB_BYTES decoded, an image carries next to no detail */
        if (max_pixels > 0 && fstat(fileno(ctx->fp), &fst) == 0 && fst.st_size > 0 &&
            (double)need > CR_PNG_BOMB_BYTES &&
            (double)need > CR_PNG_MAX_RATIO * (double)fst.st_size) {
            cr_err_set(err,
                       "cannot read PNG '%s': its %lld bytes decode to %lu x %lu pixels, %zu "
                       "bytes, %.0f times as many (a decompression bomb, or an image scaled "
                       "up with no detail); use an image of at most %.0f times its file's size "
                       "or %.0f MiB decoded",
                       path, (long long)fst.st_size, (unsigned long)w, (unsigned long)h, need,
                       (double)need / (double)fst.st_size, CR_PNG_MAX_RATIO,
                       CR_PNG_BOMB_BYTES / 1048576.0);
            goto fail;
        }
    }
    buf = malloc(need);
    rows = malloc((size_t)h * sizeof(png_bytep));
    if (!buf || !rows) {
        cr_err_set(err, "cannot read PNG '%s': out of memory for %lu x %lu pixels (%zu bytes)",
                   path, (unsigned long)w, (unsigned long)h, need);
        goto fail;
    }
    for (png_uint_32 y = 0; y < h; y++)
        rows[y] = buf + (size_t)y * rowbytes;
    png_read_image(png, rows);
    png_read_end(png, NULL);

    if (channels == 4) {
        /* Composite against black in place: out = c * alpha / 255 (rounded).
         * Writing pixel i at 3i never overtakes reading it at 4i. */
        size_t n = (size_t)w * h;
        uint8_t *p = buf;
        for (size_t i = 0; i < n; i++) {
            unsigned al = p[4 * i + 3];
            for (int c = 0; c < 3; c++)
                p[3 * i + c] = (uint8_t)((p[4 * i + c] * al + 127u) / 255u);
        }
        uint8_t *shrunk = realloc(buf, n * 3);
        if (shrunk)
            buf = shrunk;
    }

    free(rows);
    png_destroy_read_struct(&png, &info, NULL);
    *rgb = buf;
    *wout = (int)w;
    *hout = (int)h;
    return 0;

fail:
    free(rows);
    free(buf);
    png_destroy_read_struct(&png, &info, NULL);
    return -1;
}

/* Width and height from the IHDR chunk that must follow the signature (PNG
 * 11.2.2), read directly so that an absurd size is refused even when the
 * file holds nothing else (libpng reads on to the first IDAT before it hands
 * the header over). fp is positioned after the signature and is put back
 * there. Returns 0, or -1 when the header cannot be read this way (libpng
 * then reports what is wrong). */
static int cr_png_peek_size(FILE *fp, unsigned long *w, unsigned long *h)
{
    unsigned char b[16];
    long pos = ftell(fp);
    size_t got;
    if (pos < 0)
        return -1; /* not seekable: a pipe */
    got = fread(b, 1, sizeof b, fp);
    if (fseek(fp, pos, SEEK_SET) != 0 || got != sizeof b || memcmp(b + 4, "IHDR", 4) != 0)
        return -1;
    *w = (unsigned long)b[8] << 24 | (unsigned long)b[9] << 16 | (unsigned long)b[10] << 8 |
         b[11];
    *h = (unsigned long)b[12] << 24 | (unsigned long)b[13] << 16 | (unsigned long)b[14] << 8 |
         b[15];
    return 0;
}

int cr_png_read(const char *path, long long max_pixels, uint8_t **rgb, int *w, int *h,
                cr_err *err)
{
    unsigned long pw, ph;
    unsigned char sig[8];
    cr_png_ctx ctx;
    size_t got;
    FILE *fp;
    int rc;

    *rgb = NULL;
    *w = *h = 0;
    fp = fopen(path, "rb");
    if (!fp)
        return cr_err_set(err, "cannot read PNG '%s': %s", path, strerror(errno));
    got = fread(sig, 1, sizeof sig, fp);
    if (got != sizeof sig && ferror(fp)) {
        int e = errno;
        fclose(fp);
        return cr_err_set(err, "cannot read PNG '%s': %s", path, strerror(e));
    }
    if (got != sizeof sig || png_sig_cmp(sig, 0, sizeof sig) != 0) {
        fclose(fp);
        return cr_err_set(err, "cannot read PNG '%s': not a PNG file (wrong signature%s)", path,
                          got == 0 ? ", the file is empty" : "");
    }
    if (max_pixels > 0 && cr_png_peek_size(fp, &pw, &ph) == 0 &&
        (unsigned long long)pw * ph > (unsigned long long)max_pixels) {
        fclose(fp);
        return cr_png_too_large(err, path, pw, ph, max_pixels);
    }
    memset(&ctx, 0, sizeof ctx);
    ctx.fp = fp;
    rc = cr_png_read_body(&ctx, path, max_pixels, rgb, w, h, err);
    fclose(fp);
    return rc;
}
