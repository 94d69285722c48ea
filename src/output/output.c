/* curray io: the files of one frame: c_<k>.png, r_<k>.png, d_<k>.csv (output.h). */
#include "output.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/atomic.h"
#include "../base/fsutil.h"
#include "info.h"
#include "../base/png_io.h"
#include "../base/shortest.h"

/* stdio buffer for the large outputs (CSV): 1 MiB keeps write() calls few. */
#define CR_OUT_BUFSIZE (1u << 20)

/* 0..255, rounded to nearest (halves away from zero). */
static uint8_t cr_to_byte(double v)
{
    if (!(v > 0.0))
        return 0;
    if (v >= 255.0)
        return 255;
    return (uint8_t)lround(v);
}

/* (6.9.1) with z = omega_r / omega_s >= 0 (z = +inf allowed: pure blue).
 * The horizon is taken as z = 0 whatever the pixel stores: light from it is
 * infinitely redshifted. A negative ratio (-1: source inside the ergosphere)
 * on a disc or sphere is green; a NaN ratio there is black like every pixel
 * without a source (sky, error, limit, outside, none). */
/* (6.9.1) for z >= 0 (+inf: pure blue). */
static cr_rgb cr_shift_rgb(double z)
{
    cr_rgb c = {0, 0, 0};
    double b = 255.0 * atan(z) * (2.0 / CR_PI);
    c.r = cr_to_byte(255.0 - b);
    c.b = cr_to_byte(b);
    return c;
}

cr_rgb cr_redshift_color(const cr_pixel *p)
{
    cr_rgb c = {0, 0, 0};
    double z;

    switch (p->outcome) {
    case CR_OUT_HORIZON:
        z = 0.0;
        break;
    case CR_OUT_DISC:
    case CR_OUT_SPHERE:
        z = p->redshift;
        if (z != z)
            return c;
        if (z < 0.0) {
            c.g = 255;
            return c;
        }
        break;
    default:
        return c;
    }
    return cr_shift_rgb(z);
}

cr_rgb cr_redshift_sky_color(const cr_pixel *p)
{
    if (p->outcome == CR_OUT_SKY && p->redshift >= 0.0) /* false for NaN */
        return cr_shift_rgb(p->redshift);
    return cr_redshift_color(p);
}

cr_rgb cr_bolometric_color(const cr_pixel *p)
{
    cr_rgb c = {0, 0, 0};
    double v;
    if (p->outcome != CR_OUT_DISC || !(p->bolo > 0.0))
        return c;
    v = 255.0 * (log10(p->bolo) + 3.0) / 4.0;
    c.r = c.g = c.b = cr_to_byte(v);
    return c;
}

cr_rgb cr_order_color(const cr_pixel *p)
{
    static const cr_rgb pal[5] = {
        {255, 176, 64}, {64, 160, 255}, {96, 255, 96}, {255, 64, 255}, {255, 255, 255}};
    cr_rgb c = {0, 0, 0};
    if ((p->outcome != CR_OUT_DISC && p->outcome != CR_OUT_SPHERE) || p->order < 0)
        return c;
    return pal[p->order < 4 ? p->order : 4];
}

static int cr_frame_path(char *out, size_t n, const char *dir, const char *prefix, int k,
                         const char *ext, cr_err *err)
{
    char name[64];
    snprintf(name, sizeof name, "%s_%d.%s", prefix, k, ext);
    if (cr_path_join(out, n, dir, name) != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    return 0;
}

static int cr_check_frame(const cr_pixel *px, int w, int h, cr_err *err)
{
    if (!px || w <= 0 || h <= 0 || (long long)w * h > 0x7fffffffLL / 3)
        return cr_err_set(err, "cannot write a frame of %d x %d pixels", w, h);
    return 0;
}

/* Shared by the c_, r_ and b_ PNGs: colour each pixel by colour(pixel)
 * (NULL: the pixel's own colour), write the file. */
static int cr_output_png(const char *dir, const char *prefix, int k, const cr_pixel *px, int w,
                         int h, cr_rgb (*colour)(const cr_pixel *), cr_err *err)
{
    char path[4096];
    size_t n;
    uint8_t *rgb;
    int rc;

    if (cr_check_frame(px, w, h, err) != 0 ||
        cr_frame_path(path, sizeof path, dir, prefix, k, "png", err) != 0)
        return -1;
    n = (size_t)w * (size_t)h;
    rgb = malloc(n * 3);
    if (!rgb)
        return cr_err_set(err, "writing %s: out of memory", path);
    for (size_t i = 0; i < n; i++) {
        cr_rgb c = colour ? colour(&px[i]) : px[i].color;
        rgb[3 * i] = c.r;
        rgb[3 * i + 1] = c.g;
        rgb[3 * i + 2] = c.b;
    }
    rc = cr_png_write(path, w, h, rgb, err);
    free(rgb);
    return rc;
}

int cr_output_color_png(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err)
{
    return cr_output_png(dir, "c", k, px, w, h, NULL, err);
}

int cr_output_redshift_png(const char *dir, int k, const cr_pixel *px, int w, int h, int sky,
                           cr_err *err)
{
    return cr_output_png(dir, "r", k, px, w, h, sky ? cr_redshift_sky_color : cr_redshift_color,
                         err);
}

int cr_output_bolometric_png(const char *dir, int k, const cr_pixel *px, int w, int h,
                             cr_err *err)
{
    return cr_output_png(dir, "b", k, px, w, h, cr_bolometric_color, err);
}

/* Decimal digits of v at p; returns the end. */
static char *cr_put_uint(char *p, unsigned long v)
{
    char tmp[24];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n)
        *p++ = tmp[--n];
    return p;
}

/* Decimal digits of a count v >= -1 at p; returns the end. */
static char *cr_put_int(char *p, int v)
{
    if (v < 0) {
        *p++ = '-';
        return cr_put_uint(p, (unsigned long)-(long)v);
    }
    return cr_put_uint(p, (unsigned long)v);
}

/* The shortest text that strtod reads back as v (shortest.h). */
static char *cr_put_double(char *p, double v)
{
    /* fast paths, same text: the "undefined" marker and zero */
    if (v == -1.0) {
        memcpy(p, "-1", 2);
        return p + 2;
    }
    if (v == 0.0 && !signbit(v)) {
        *p = '0';
        return p + 1;
    }
    return p + cr_shortest_double(p, v);
}

static const char *const cr_csv_header = "x,y,r,g,b,steps,redshift,err_mean,err_std,outcome,hit_r,hit_phi,bolometric,order,theta_turns,delay\n";

int cr_output_csv_stream(FILE *fp, const char *name, const cr_pixel *px, int w, int h,
                         cr_err *err)
{
    char line[256];

    if (cr_check_frame(px, w, h, err) != 0)
        return -1;
    fputs(cr_csv_header, fp);
    for (int y = 0; y < h && !ferror(fp); y++) {
        for (int x = 0; x < w; x++) {
            const cr_pixel *q = &px[(size_t)y * w + x];
            cr_pixel_values v = cr_pixel_csv_values(q);
            char *p = line;
            p = cr_put_uint(p, (unsigned long)x);
            *p++ = ',';
            p = cr_put_uint(p, (unsigned long)y);
            *p++ = ',';
            p = cr_put_uint(p, q->color.r);
            *p++ = ',';
            p = cr_put_uint(p, q->color.g);
            *p++ = ',';
            p = cr_put_uint(p, q->color.b);
            *p++ = ',';
            p = cr_put_uint(p, q->steps);
            *p++ = ',';
            p = cr_put_double(p, v.redshift);
            *p++ = ',';
            p = cr_put_double(p, q->err_mean);
            *p++ = ',';
            p = cr_put_double(p, q->err_std);
            *p++ = ',';
            const char *o = cr_outcome_name(q->outcome);
            size_t ol = strlen(o);
            memcpy(p, o, ol);
            p += ol;
            *p++ = ',';
            p = cr_put_double(p, v.hit_r);
            *p++ = ',';
            p = cr_put_double(p, v.hit_phi);
            *p++ = ',';
            p = cr_put_double(p, v.bolometric);
            *p++ = ',';
            p = cr_put_int(p, v.order);
            *p++ = ',';
            p = cr_put_int(p, v.theta_turns);
            *p++ = ',';
            if (v.delay == v.delay) {
                p = cr_put_double(p, v.delay);
            } else {
                memcpy(p, "nan", 3);
                p += 3;
            }
            *p++ = '\n';
            fwrite(line, 1, (size_t)(p - line), fp);
        }
        /* the reason of the first failed write (a full disk): a later
         * fflush may find nothing left to write */
        if (ferror(fp)) {
            int e = errno ? errno : EIO;
            return cr_err_set(err, "writing %s: %s", name, strerror(e));
        }
    }
    return cr_stream_check(fp, name, err);
}

int cr_output_csv(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err)
{
    char path[4096];
    cr_atomic a;
    char *buf;
    int rc;

    if (cr_check_frame(px, w, h, err) != 0 ||
        cr_frame_path(path, sizeof path, dir, "d", k, "csv", err) != 0)
        return -1;
    if (cr_atomic_open(&a, path, err) != 0)
        return -1;
    buf = malloc(CR_OUT_BUFSIZE); /* without it stdio's default buffer still works */
    if (buf)
        setvbuf(a.fp, buf, _IOFBF, CR_OUT_BUFSIZE);
    rc = cr_output_csv_stream(a.fp, path, px, w, h, err);
    if (rc == 0)
        rc = cr_atomic_commit(&a, err); /* closes the stream, also on failure */
    else
        cr_atomic_abort(&a);
    free(buf);
    return rc;
}

int cr_output_write_color(const cr_frame_output *o, cr_err *err)
{
    return cr_output_color_png(o->dir, o->k, o->px, o->frame->width, o->frame->height, err);
}

int cr_output_write_redshift(const cr_frame_output *o, cr_err *err)
{
    return cr_output_redshift_png(o->dir, o->k, o->px, o->frame->width, o->frame->height,
                                  o->scene->redshift_sky, err);
}

int cr_output_write_csv(const cr_frame_output *o, cr_err *err)
{
    return cr_output_csv(o->dir, o->k, o->px, o->frame->width, o->frame->height, err);
}

int cr_output_write_bolometric(const cr_frame_output *o, cr_err *err)
{
    return cr_output_bolometric_png(o->dir, o->k, o->px, o->frame->width, o->frame->height, err);
}

int cr_output_write_order(const cr_frame_output *o, cr_err *err)
{
    return cr_output_png(o->dir, "n", o->k, o->px, o->frame->width, o->frame->height,
                         cr_order_color, err);
}
