/* curray orbit: the worldline of a massive or charged particle as CSV
 * (docs/command-line.md, "Orbits"; the file's keys: docs/scenes.md).
 *
 *   curray orbit -s <orbit file> -o <output directory> [-q]
 *
 * Loads and checks the orbit file (nothing is written when it is refused),
 * integrates the worldline (src/core/particle.h) and writes
 * <output directory>/orbit.csv atomically, then prints the constants and
 * how the worldline ended. Exit status: 0 done, 1 error, 2 usage error.
 */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "../base/fsutil.h"
#include "../output/worldline.h"
#include "app.h"

static const char *const orbit_usage =
    "usage: curray orbit -s <orbit file> -o <output directory> [-q]\n"
    "  writes the worldline of the file's particle to <output directory>/orbit.csv\n"
    "  (columns tau, t, r, theta, phi, x, y, z, u^t, u^r, u^theta, u^phi)\n";

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

int cr_orbit_command(int argc, char **argv)
{
    static const struct option longopts[] = {{"scene_file", required_argument, 0, 's'},
                                             {"output_dir", required_argument, 0, 'o'},
                                             {"quiet", no_argument, 0, 'q'},
                                             {"help", no_argument, 0, 'h'},
                                             {0, 0, 0, 0}};
    const char *scene = NULL, *out = NULL;
    char path[4096];
    int quiet = 0, c;
    cr_particle_spec spec;
    cr_worldline_info info;
    cr_err err;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "s:o:qh", longopts, NULL)) != -1) {
        switch (c) {
        case 's':
            scene = optarg;
            break;
        case 'o':
            out = optarg;
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
    if (cr_particle_spec_load(scene, &spec, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        return CR_EXIT_ERROR;
    }
    if (cr_path_join(path, sizeof path, out, "orbit.csv")) {
        fprintf(stderr, "curray: output path too long: %s\n", out);
        return CR_EXIT_ERROR;
    }
    if (cr_mkdir_p(out, &err) || cr_worldline_write_csv(&spec, path, &info, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        return CR_EXIT_ERROR;
    }
    if (!quiet)
        printf("curray orbit: E = %.15g, L = %.15g, K = %.15g; %ld rows, %ld steps; %s\n"
               "wrote %s\n",
               info.E, info.L, info.K, info.rows, info.steps, end_text(info.ended), path);
    return CR_EXIT_OK;
}
