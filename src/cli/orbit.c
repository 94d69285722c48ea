/* curray orbit: the worldline of a massive or charged particle as CSV, and
 * with -t c its lensed picture (docs/command-line.md, "Orbits"; the file's
 * keys: docs/scenes.md).
 *
 *   curray orbit -s <orbit file> -o <output directory> [-t c] [-x W] [-y H] [-q]
 *
 * Loads and checks the orbit file and, for -t c, the scene of its view
 * section (nothing is written when either is refused), integrates the
 * worldline (src/core/particle.h) and writes <output directory>/orbit.csv;
 * with -t c it also renders frame 0 of the view's scene on the CPU and
 * draws the worldline's images over it (src/output/orbit_picture.h) into
 * orbit.png, with the images' positions in orbit_image.csv. The files
 * appear together at the end (each written atomically, orbit.csv last).
 * Prints the constants and how the worldline ended. Exit status: 0 done,
 * 1 error, 2 usage error.
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../base/fsutil.h"
#include "../base/png_io.h"
#include "../input/scene.h"
#include "../output/orbit_picture.h"
#include "../output/worldline.h"
#include "../render/cpu.h"
#include "app.h"

static const char *const orbit_usage =
    "usage: curray orbit -s <orbit file> -o <output directory> [-t c] [-x W] [-y H] [-q]\n"
    "  writes the worldline of the file's particle to <output directory>/orbit.csv\n"
    "  (columns tau, t, r, theta, phi, x, y, z, u^t, u^r, u^theta, u^phi);\n"
    "  -t c also draws it as the camera of the file's view sees it, lensed, over\n"
    "  the view's scene: orbit.png (W x H pixels, default 320 x 240) and\n"
    "  orbit_image.csv (where each point's images are)\n";

static const char *end_text(int ended)
{
    switch (ended) {
    case CR_PARTICLE_HORIZON:
        return "reached the horizon";
    case CR_PARTICLE_ESCAPED:
        return "escaped beyond r_max";
    default:
        return "followed for the whole proper time";
    }
}

/* -t for curray orbit: c only. */
static int check_types(const char *t)
{
    const char *p;
    if (!t[0]) {
        fprintf(stderr, "curray orbit: -t: empty output type; use c (the lensed picture)\n%s",
                orbit_usage);
        return -1;
    }
    for (p = t; *p; p++)
        if (*p != 'c') {
            fprintf(stderr,
                    "curray orbit: -t: '%c' is not an output of curray orbit; use c (the "
                    "lensed picture orbit.png; orbit.csv is always written)\n%s",
                    *p, orbit_usage);
            return -1;
        }
    return 0;
}

static int side_arg(const char *opt, const char *v, int *out)
{
    char *end;
    long n = strtol(v, &end, 10);
    if (!v[0] || *end || n < 1 || n > CR_OPIC_MAX_SIDE) {
        fprintf(stderr, "curray orbit: %s: expected a size from 1 to %d pixels, got '%s'\n%s",
                opt, CR_OPIC_MAX_SIDE, v, orbit_usage);
        return -1;
    }
    *out = (int)n;
    return 0;
}

/* The picture of the rows taken by v into dir: orbit.png and
 * orbit_image.csv. Returns 0, or -1 with err set and neither file left. */
static int write_picture(cr_opic_view *v, const char *dir, long *images, long *lost,
                         cr_err *err)
{
    char png[4096], csv[4096];
    const cr_frame *f = &v->ev.frame;
    size_t np = (size_t)f->width * f->height;
    cr_pixel *px = malloc(np * sizeof *px);
    uint8_t *rgb = malloc(np * 3);
    cr_opic_result r;
    int rc = -1;
    memset(&r, 0, sizeof r);
    if (!px || !rgb) {
        cr_err_set(err, "out of memory for a %d x %d picture", f->width, f->height);
        goto done;
    }
    if (cr_path_join(png, sizeof png, dir, "orbit.png") ||
        cr_path_join(csv, sizeof csv, dir, "orbit_image.csv")) {
        cr_err_set(err, "output path too long: %s", dir);
        goto done;
    }
    if (cr_cpu_render(f, 0, px, NULL, NULL, NULL, err) ||
        cr_opic_view_picture(v, px, rgb, &r, err) || cr_opic_write_csv(&r, csv, err))
        goto done;
    if (cr_png_write(png, f->width, f->height, rgb, err)) {
        unlink(csv);
        goto done;
    }
    *images = r.n;
    *lost = r.lost;
    rc = 0;
done:
    cr_opic_result_free(&r);
    free(px);
    free(rgb);
    return rc;
}

int cr_orbit_command(int argc, char **argv)
{
    static const struct option longopts[] = {{"scene_file", required_argument, 0, 's'},
                                             {"output_dir", required_argument, 0, 'o'},
                                             {"output_type", required_argument, 0, 't'},
                                             {"x_res", required_argument, 0, 'x'},
                                             {"y_res", required_argument, 0, 'y'},
                                             {"quiet", no_argument, 0, 'q'},
                                             {"help", no_argument, 0, 'h'},
                                             {0, 0, 0, 0}};
    const char *scene = NULL, *out = NULL, *types = NULL;
    char path[4096];
    int quiet = 0, c, w = CR_OPIC_DEFAULT_W, h = CR_OPIC_DEFAULT_H, picture;
    int rc = CR_EXIT_ERROR;
    long images = 0, lost = 0;
    cr_particle_spec spec;
    cr_worldline_info info;
    cr_opic_view view;
    cr_atomic a;
    cr_err err;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "s:o:t:x:y:qh", longopts, NULL)) != -1) {
        switch (c) {
        case 's':
            scene = optarg;
            break;
        case 'o':
            out = optarg;
            break;
        case 't':
            types = optarg;
            break;
        case 'x':
            if (side_arg("-x", optarg, &w))
                return CR_EXIT_USAGE;
            break;
        case 'y':
            if (side_arg("-y", optarg, &h))
                return CR_EXIT_USAGE;
            break;
        case 'q':
            quiet = 1;
            break;
        case 'h':
            fputs(orbit_usage, stdout);
            return CR_EXIT_OK;
        default:
            fprintf(stderr, "curray orbit: unknown option or missing value '%s'\n%s",
                    argv[optind - 1], orbit_usage);
            return CR_EXIT_USAGE;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "curray orbit: unexpected argument '%s'\n%s", argv[optind], orbit_usage);
        return CR_EXIT_USAGE;
    }
    if (!scene || !out) {
        fprintf(stderr, "curray orbit: %s is required\n%s", !scene ? "-s" : "-o", orbit_usage);
        return CR_EXIT_USAGE;
    }
    if (types && check_types(types))
        return CR_EXIT_USAGE;
    picture = types != NULL;
    if (cr_particle_spec_load(scene, &spec, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        return CR_EXIT_ERROR;
    }
    memset(&view, 0, sizeof view);
    if (picture && cr_opic_view_open(&view, &spec, scene, w, h, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        return CR_EXIT_ERROR;
    }
    if (cr_path_join(path, sizeof path, out, "orbit.csv")) {
        fprintf(stderr, "curray: output path too long: %s\n", out);
        goto done;
    }
    if (cr_mkdir_p(out, &err) ||
        cr_worldline_write_csv_open(&spec, path, picture ? cr_opic_view_row : NULL, &view,
                                    &a, &info,
                                    &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        goto done;
    }
    if (picture) {
        if (write_picture(&view, out, &images, &lost, &err)) {
            cr_atomic_abort(&a);
            fprintf(stderr, "curray: %s\n", err.msg);
            goto done;
        }
    }
    if (cr_atomic_commit(&a, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        goto done;
    }
    if (!quiet) {
        printf("curray orbit: E = %.15g, L = %.15g, K = %.15g; %ld rows, %ld steps; %s\n"
               "wrote %s\n",
               info.E, info.L, info.K, info.rows, info.steps, end_text(info.ended), path);
        if (picture)
            printf("curray orbit: %ld images of %ld points in orders 0 to %d (%ld points "
                   "without an image); wrote %s/orbit.png, %s/orbit_image.csv\n",
                   images, view.n, spec.view.orders - 1, lost, out, out);
    }
    rc = CR_EXIT_OK;
done:
    cr_opic_view_free(&view);
    return rc;
}
