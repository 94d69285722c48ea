/* curray io: f_<k>.fits (fits.h). */
#include "fits.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/defs.h"
#include "../base/atomic.h"
#include "../base/fsutil.h"
#include "info.h"
#include "module.h"
#include "output.h"
#include "../input/sysconfig.h"

/* Quantities of the image extensions, in the file's order. */
enum { CR_F_REDSHIFT, CR_F_HIT_R, CR_F_HIT_PHI, CR_F_BOLO, CR_F_OUTCOME, CR_F_STEPS, CR_F_ERR,
       CR_F_STD, CR_F_ORDER, CR_F_THTURNS, CR_F_DELAY, CR_F_N };

/* One image extension: its EXTNAME, BUNIT, comment and the bytes of one
 * value, which also fix its FITS type (cr_fits_image): 8 float64, 4 uint32,
 * 2 int16, 1 uint8. The writer and cr_fits_memory both read this table. */
static const struct {
    const char *name, *unit, *comment;
    int bytes;
} cr_fits_ext[CR_F_N] = {
    {"REDSHIFT", "", "frequency ratio nu_obs/nu_em; NaN: no source", 8},
    {"HIT_R", "M", "BL radius of the disc/sphere hit; NaN: none", 8},
    {"HIT_PHI", "rad", "BL azimuth of the hit in [0, 2 pi); NaN: none", 8},
    {"BOLO", "", "g^4 F / F_max of a Keplerian disc hit; NaN: none", 8},
    {"OUTCOME", "", "what the ray reached: codes in OUTCOME0..6", 1},
    {"STEPS", "", "integrator steps of the pixel", 4},
    {"NULLERR", "", "mean of the ray's error monitor", 8},
    {"NULLSTD", "", "standard deviation of the error monitor", 8},
    {"ORDER", "", "equator crossings before the hit or end; -1: none", 2},
    {"THTURNS", "", "polar turning points before it; -1: none", 2},
    {"DELAY", "M", "coordinate-time delay of the hit; NaN: none", 8},
};

int cr_fits_pixel_bytes(void)
{
    int q, n = 0;
    for (q = 0; q < CR_F_N; q++)
        n += cr_fits_ext[q].bytes;
    return n;
}

int cr_fits_hdus(void)
{
    return 1 + CR_F_N; /* the primary HDU and one extension a quantity */
}

double cr_fits_memory(int w, int h)
{
    /* the planes; each HDU's keywords, a few 2880-byte blocks; one row of
     * the widest value */
    return (double)cr_fits_pixel_bytes() * (double)w * (double)h +
           (double)cr_fits_hdus() * 4.0 * 2880.0 + 8.0 * (double)w;
}

/* What curray_fits.so gives the program (module.h). */
typedef struct cr_fits_module {
    cr_module_header head;
    int (*write)(const char *dir, int k, int n, const cr_scene *s, const cr_frame *f,
                 const cr_pixel *px, cr_err *err);
} cr_fits_module;

#define CR_FITS_MODULE_FILE "curray_fits" CURRAY_MODULE_SUFFIX
#define CR_FITS_MODULE_NEEDS "cfitsio's library libcfitsio (Debian: apt-get install libcfitsio10, " \
                             "or libcfitsio-dev of tools/install-deps.sh)"

#if defined(CURRAY_FITS_MODULE_HOST)

static const cr_fits_module *cr_fits_module_get(cr_err *err)
{
    return cr_module_load(CR_FITS_MODULE_FILE, "curray_fits_module", "FITS module",
                          CR_FITS_MODULE_NEEDS, err);
}

int cr_fits_available(cr_err *err)
{
    cr_err e;
    if (cr_fits_module_get(&e))
        return 1;
    cr_err_set(err, "-t f: %s", e.msg);
    return 0;
}

int cr_output_fits(const char *dir, int k, int n, const cr_scene *s, const cr_frame *f,
                   const cr_pixel *px, cr_err *err)
{
    const cr_fits_module *m = cr_fits_module_get(err);
    return m ? m->write(dir, k, n, s, f, px, err) : -1;
}

#elif !defined(CURRAY_HAVE_FITS)

int cr_fits_available(cr_err *err)
{
    cr_err_set(err, "%s", CR_FITS_MISSING);
    return 0;
}

int cr_output_fits(const char *dir, int k, int n, const cr_scene *s, const cr_frame *f,
                   const cr_pixel *px, cr_err *err)
{
    (void)dir, (void)k, (void)n, (void)s, (void)f, (void)px;
    return cr_err_set(err, CR_FITS_MISSING);
}

#else

#include <fitsio.h>

int cr_fits_available(cr_err *err)
{
    (void)err;
    return 1;
}

/* Value of quantity q at pixel p, the CSV's (cr_pixel_csv_values), NaN
 * where the CSV writes -1. */
static double cr_fits_value(int q, const cr_pixel *p)
{
    cr_pixel_values v = cr_pixel_csv_values(p);
    double x;
    switch (q) {
    case CR_F_REDSHIFT: x = v.redshift; break;
    case CR_F_HIT_R: x = v.hit_r; break;
    case CR_F_HIT_PHI: x = v.hit_phi; break;
    case CR_F_BOLO: x = v.bolometric; break;
    case CR_F_ERR: return p->err_mean;
    case CR_F_DELAY: return v.delay;
    default: return p->err_std;
    }
    return x == -1.0 ? NAN : x;
}

/* The frame's keywords on the current (primary) HDU. */
static void cr_fits_keys(fitsfile *ff, int k, int n, const cr_scene *s, const cr_frame *f,
                         int *st)
{
    const double deg = 180.0 / CR_PI;
    double m = cr_anim_at(s->m, k, n), v;
    char word[32];
    int o;
    fits_write_key_str(ff, "CREATOR", "curray " CURRAY_VERSION, "relativistic raytracer", st);
    fits_write_key_lng(ff, "FRAME", k, "frame number, from 0", st);
    fits_write_key_lng(ff, "NFRAMES", n, "frames in the run", st);
    fits_write_key_str(ff, "METRIC", "Kerr-Newman", "Boyer-Lindquist coordinates", st);
    fits_write_key_str(ff, "UNITS", "G = c = 1", "lengths in units of M (BH_MASS)", st);
    fits_write_key_str(ff, "SIGNATUR", "-+++", "metric signature", st);
    fits_write_key_dbl(ff, "BH_MASS", m, 15, "M in the scene file's length unit", st);
    fits_write_key_dbl(ff, "BH_SPIN", f->metric.a, 15, "a / M", st);
    fits_write_key_dbl(ff, "BH_CHRG", f->metric.q, 15, "Q / M", st);
    if (f->obs_at_inf) {
        fits_write_key_log(ff, "OBS_INF", 1, "observer at infinity (image plane)", st);
        fits_write_key_dbl(ff, "HEXTENT", f->observer.hextent, 15, "[M] image plane width", st);
        fits_write_key_dbl(ff, "VEXTENT", f->observer.vextent, 15, "[M] image plane height", st);
    } else {
        fits_write_key_log(ff, "OBS_INF", 0, "observer at finite r", st);
        fits_write_key_dbl(ff, "OBS_R", f->observer.r, 15, "[M] observer BL radius", st);
        fits_write_key_dbl(ff, "HFOV", f->observer.hfov * deg, 15, "[deg] horizontal fov", st);
        fits_write_key_dbl(ff, "VFOV", f->observer.vfov * deg, 15, "[deg] vertical fov", st);
    }
    fits_write_key_dbl(ff, "OBS_TH", f->observer.theta * deg, 15, "[deg] observer BL theta", st);
    fits_write_key_dbl(ff, "OBS_PH", f->observer.phi * deg, 15, "[deg] observer BL phi", st);
    fits_write_key_dbl(ff, "OBS_ROLL", f->observer.roll * deg, 15, "[deg] camera roll", st);
    fits_write_key_dbl(ff, "OBS_PTCH", f->observer.pitch * deg, 15, "[deg] camera pitch", st);
    fits_write_key_dbl(ff, "OBS_YAW", f->observer.yaw * deg, 15, "[deg] camera yaw", st);
    fits_write_key_str(ff, "INTEGRAT", cr_integrator_name(f->integrator), "geodesic integrator",
                       st);
    v = f->tolerance;
    fits_write_key_dbl(ff, "TOLERANC", v, 15, "mino error tolerance", st);
    fits_write_key_lng(ff, "SAMPLES", f->samples > 1 ? f->samples : 1,
                       "sub-pixel rays per side", st);
    if (s->path)
        fits_write_key_longstr(ff, "SCENE", s->path, "scene file", st);
    for (o = 0; o < CR_OUT_COUNT_; o++) {
        snprintf(word, sizeof word, "OUTCOME%d", o);
        fits_write_key_str(ff, word, cr_outcome_name(o), "OUTCOME code meaning", st);
    }
}

/* One image extension of quantity q (rows flipped: FITS row 1 at the bottom). */
static void cr_fits_image(fitsfile *ff, int q, const cr_pixel *px, int w, int h, void *row,
                          int *st)
{
    long naxes[2];
    int y, x;
    int bytes = cr_fits_ext[q].bytes;
    int bitpix = bytes == 1 ? BYTE_IMG : bytes == 2 ? SHORT_IMG : bytes == 4 ? ULONG_IMG
                                                                             : DOUBLE_IMG;
    int type = bytes == 1 ? TBYTE : bytes == 2 ? TSHORT : bytes == 4 ? TUINT : TDOUBLE;
    naxes[0] = w;
    naxes[1] = h;
    fits_create_img(ff, bitpix, 2, naxes, st);
    fits_write_key_str(ff, "EXTNAME", cr_fits_ext[q].name, cr_fits_ext[q].comment, st);
    fits_write_key_str(ff, "BUNIT", cr_fits_ext[q].unit, "unit", st);
    for (y = 0; y < h && *st == 0; y++) {
        const cr_pixel *p = px + (size_t)(h - 1 - y) * (size_t)w;
        for (x = 0; x < w; x++) {
            if (bytes == 1) /* OUTCOME */
                ((unsigned char *)row)[x] = p[x].outcome;
            else if (bytes == 4) /* STEPS */
                ((unsigned int *)row)[x] = p[x].steps;
            else if (bytes == 2) { /* ORDER, THTURNS */
                cr_pixel_values v = cr_pixel_csv_values(&p[x]);
                ((short *)row)[x] = (short)(q == CR_F_ORDER ? v.order : v.theta_turns);
            }
            else
                ((double *)row)[x] = cr_fits_value(q, &p[x]);
        }
        fits_write_img(ff, type, (LONGLONG)y * w + 1, w, row, st);
    }
}

int cr_output_fits(const char *dir, int k, int n, const cr_scene *s, const cr_frame *f,
                   const cr_pixel *px, cr_err *err)
{
    char path[4096], name[64], msg[FLEN_ERRMSG];
    int w = f->width, h = f->height;
    void *row = malloc(sizeof(double) * (size_t)(w > 0 ? w : 1));
    void *mem = NULL;
    size_t memsize = 0;
    fitsfile *ff = NULL;
    int st = 0, q, rc = -1;
    LONGLONG head0, data0, data1;
    cr_atomic a;

    snprintf(name, sizeof name, "f_%d.fits", k);
    if (cr_path_join(path, sizeof path, dir, name) != 0) {
        cr_err_set(err, "output folder name too long: '%s'", dir);
        goto done;
    }
    if (!row) {
        cr_err_set(err, "writing %s: out of memory", path);
        goto done;
    }
    fits_create_memfile(&ff, &mem, &memsize, 2880 * 64, realloc, &st);
    fits_create_img(ff, BYTE_IMG, 0, NULL, &st);
    cr_fits_keys(ff, k, n, s, f, &st);
    for (q = 0; q < CR_F_N; q++)
        cr_fits_image(ff, q, px, w, h, row, &st);
    fits_get_hduaddrll(ff, &head0, &data0, &data1, &st);
    fits_close_file(ff, &st);
    if (st) {
        fits_get_errstatus(st, msg);
        cr_err_set(err, "writing %s: cfitsio: %s", path, msg);
        goto done;
    }
    /* the file ends with the last HDU's data, padded to 2880-byte blocks */
    data1 = (data1 + 2879) / 2880 * 2880;
    if ((size_t)data1 > memsize) {
        cr_err_set(err, "writing %s: cfitsio produced %lld of %lld bytes", path,
                   (long long)memsize, (long long)data1);
        goto done;
    }
    if (cr_atomic_open(&a, path, err))
        goto done;
    fwrite(mem, 1, (size_t)data1, a.fp);
    rc = cr_atomic_commit(&a, err);
done:
    free(mem);
    free(row);
    return rc;
}

#if defined(CURRAY_FITS_MODULE)
/* The entry of curray_fits.so. */
CR_MODULE_EXPORT const cr_fits_module *curray_fits_module(void);
CR_MODULE_EXPORT const cr_fits_module *curray_fits_module(void)
{
    static const cr_fits_module m = {{CURRAY_VERSION, CR_MODULE_LAYOUT}, cr_output_fits};
    return &m;
}
#endif

#endif

int cr_output_write_fits(const cr_frame_output *o, cr_err *err)
{
    return cr_output_fits(o->dir, o->k, o->n, o->scene, o->frame, o->px, err);
}
