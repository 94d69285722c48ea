/* Cheaper ways to the same pixels.
 *
 * The early stop (frame.h cr_frame_prepare): with a plain sky an outgoing
 * ray beyond the scene's objects and photon orbits ends as sky there, not at
 * the observer's radius. For the bench scenes of the a = 0.9 disc seen from
 * r = 30, 100 and 1e6 M (bench/scenes), under mino and (r <= 100) rk4,
 * every pixel of a 48x48 image must be the same, bit for bit (outcome,
 * colour, object, redshift, hit point, image order), as with the scene
 * boundary where it was before (at the observer's r + 1 M, set by hand into
 * the frame), each ray must take no more steps, and the image fewer in all.
 * Only a sky pixel's order and theta_turns, the crossings and turning
 * points counted until its ray ends, may differ (their number is printed):
 * a sky ray now ends at the scene's radius, as from the observer at
 * infinity.
 *
 * The packet path (render/cpu_packet.c) against the scalar path, the
 * reference: frame 0 of every scene in scenes/ at 96x64 under the default
 * integrator, rendered by cr_cpu_render_rows_path on the scalar path and on
 * each packet path this CPU has (AVX2, AVX-512), 2 threads. Required for
 * every pixel: the same outcome, object, image order (order, theta_turns)
 * and colour, except where a hit lies
 * within 1e-9 (radius relative, azimuth absolute) of the scalar one on a
 * class edge (listed; none are expected, as the lanes round as the scalar
 * code does); redshift, bolometric brightness and hit point within 1e-12
 * relative; the same steps; the error monitor (err_mean, err_std) and the
 * emission delay bit for bit (the lanes keep the scalar bookkeeping's
 * order of operations). The counts of pixels equal bit for bit are
 * printed. The step and turn limits: demo.yml with max_steps 6 and with
 * max_turns 0.05, both paths the same, limit pixels required. Science
 * frames (cr_frame.science) of three scenes, both paths the same. A frame
 * with 3 x 3 samples (the packet path hands it to the scalar tracer) and
 * frames with cancelled renders are not covered here.
 *
 * The dispatch: cr_cpu_simd_pick for every combination of cpu.simd and
 * CPU features (scalar without AVX2, with cpu.simd off, or in a build
 * without the packet path); cr_cpu_simd_path with CURRAY_TEST_CPU_FEATURES
 * taking AVX2 (and AVX-512) away.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <dirent.h>

#include "core/trace.h"
#include "input/scene.h"
#include "render/cpu.h"

#define PK_MAX_SPHERES 16

/* Frame 0 of scene file path (relative to the source folder) at w x h under
 * integrator into f (its spheres in buf). */
static void pk_frame(const char *path, int integrator, int w, int h, cr_scene *s, cr_frame *f,
                     cr_sphere *buf)
{
    char full[1024];
    cr_trace_settings ts = cr_trace_defaults();
    cr_err err;
    snprintf(full, sizeof full, "%s/%s", CR_SOURCE_DIR, path);
    if (cr_scene_load(full, s, &err) != 0)
        fail_msg("%s: %s", path, err.msg);
    assert_true(s->n_spheres <= PK_MAX_SPHERES);
    ts.integrator = integrator;
    if (cr_scene_frame(s, 0, 1, w, h, &ts, f, buf, &err) != 0)
        fail_msg("%s: %s", path, err.msg);
}

static int pk_same_pixel(const cr_pixel *a, const cr_pixel *b)
{
    return a->outcome == b->outcome && a->object == b->object && a->order == b->order &&
           a->theta_turns == b->theta_turns && a->color.r == b->color.r &&
           a->color.g == b->color.g && a->color.b == b->color.b &&
           memcmp(&a->redshift, &b->redshift, sizeof a->redshift) == 0 &&
           memcmp(&a->hit_r, &b->hit_r, sizeof a->hit_r) == 0 &&
           memcmp(&a->hit_phi, &b->hit_phi, sizeof a->hit_phi) == 0;
}

static void test_early_stop_exact(void **state)
{
    static const char *const scenes[] = {"bench/scenes/distance-r30.yml",
                                         "bench/scenes/mino-r100.yml",
                                         "bench/scenes/distance-r1e6.yml"};
    const int W = 48, H = 48;
    int is, ig;
    (void)state;
    for (is = 0; is < 3; is++)
        for (ig = 0; ig < 2; ig++) {
            int integ = ig == 0 ? CR_INTEG_MINO : CR_INTEG_RK4;
            cr_scene s;
            cr_sphere buf[PK_MAX_SPHERES];
            cr_frame f, old;
            long n_new = 0, n_old = 0, n_sky = 0, n_counts = 0;
            int i, j;
            if (integ == CR_INTEG_RK4 && is == 2)
                continue; /* rk4 from 1e6 M takes its step limit's time */
            pk_frame(scenes[is], integ, W, H, &s, &f, buf);
            assert_null(f.sky.rgb);
            old = f;
            old.r_max = fmax(f.r_max, f.observer.r + 1.0);
            old.w_sky = 1.0 / old.r_max;
            assert_true(f.r_max < old.r_max);
            for (j = 0; j < H; j++)
                for (i = 0; i < W; i++) {
                    cr_pixel a = cr_trace_pixel(&f, i, j), b = cr_trace_pixel(&old, i, j);
                    if (a.outcome == CR_OUT_SKY && b.outcome == CR_OUT_SKY &&
                        (a.order != b.order || a.theta_turns != b.theta_turns)) {
                        /* counted to the ray's end, which moved in */
                        n_counts++;
                        b.order = a.order;
                        b.theta_turns = a.theta_turns;
                    }
                    if (!pk_same_pixel(&a, &b))
                        fail_msg("%s %s: pixel (%d,%d) outcome %d/%d redshift %.17g/%.17g",
                                 scenes[is], ig ? "rk4" : "mino", i, j, a.outcome, b.outcome,
                                 a.redshift, b.redshift);
                    if (a.steps > b.steps)
                        fail_msg("%s: pixel (%d,%d) takes %u steps, %u before", scenes[is], i,
                                 j, a.steps, b.steps);
                    n_new += a.steps;
                    n_old += b.steps;
                    n_sky += a.outcome == CR_OUT_SKY;
                }
            print_message("%s %s: %ld steps, %ld to the old boundary (%.2f), %ld sky pixels, "
                          "%ld of them with other counts\n",
                          scenes[is], ig ? "rk4" : "mino", n_new, n_old, (double)n_new / n_old,
                          n_sky, n_counts);
            assert_true(n_sky > 0);
            assert_true(n_new < n_old);
            cr_scene_free(&s);
        }
}

/* ---- the packet path against the scalar path ----------------------------- */

static int pk_cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static double pk_rel(double a, double b)
{
    double d = fabs(a - b), m = fmax(fabs(a), fabs(b));
    if (a == b || (a != a && b != b))
        return 0.0;
    return m > 0.0 ? d / m : d;
}

/* A science frame (cr_frame.science) in pk_compare_limits: set by
 * test_packet_science. */
static int pk_science;

/* One scene's comparison; returns the number of failures. max_steps,
 * max_turns > 0 replace the frame's limits; *n_limit (if not NULL) gets the
 * number of pixels the scalar path ends as limit. */
static int pk_compare_limits(const char *name, int path, long max_steps, double max_turns,
                             long *n_limit)
{
    enum { W = 96, H = 64 };
    static cr_pixel ref[W * H], got[W * H];
    char full[1024];
    cr_scene s;
    cr_sphere buf[PK_MAX_SPHERES];
    cr_frame f;
    cr_err err;
    long same_bits = 0, edge = 0, bad = 0, bad_steps = 0, bad_book = 0;
    double worst_g = 0.0;
    int k;
    snprintf(full, sizeof full, "scenes/%s", name);
    pk_frame(full, cr_trace_defaults().integrator, W, H, &s, &f, buf);
    if (max_steps > 0)
        f.max_steps = max_steps;
    if (max_turns > 0.0)
        f.max_turns = max_turns;
    f.science = pk_science;
    if (cr_cpu_render_rows_path(&f, 0, H, 2, CR_CPU_SIMD_SCALAR, ref, NULL, NULL, NULL, &err) ||
        cr_cpu_render_rows_path(&f, 0, H, 2, path, got, NULL, NULL, NULL, &err))
        fail_msg("%s: %s", name, err.msg);
    if (n_limit)
        *n_limit = 0;
    for (k = 0; k < W * H; k++) {
        const cr_pixel *a = &ref[k], *b = &got[k];
        double dg = pk_rel(a->redshift, b->redshift);
        int same_class = a->outcome == b->outcome && a->object == b->object &&
                         a->order == b->order && a->theta_turns == b->theta_turns &&
                         a->color.r == b->color.r && a->color.g == b->color.g &&
                         a->color.b == b->color.b;
        int same_book = memcmp(&a->err_mean, &b->err_mean, sizeof a->err_mean) == 0 &&
                        memcmp(&a->err_std, &b->err_std, sizeof a->err_std) == 0 &&
                        memcmp(&a->delay, &b->delay, sizeof a->delay) == 0;
        if (n_limit)
            *n_limit += a->outcome == CR_OUT_LIMIT;
        same_bits += pk_same_pixel(a, b) && a->steps == b->steps && same_book &&
                     memcmp(&a->bolo, &b->bolo, sizeof a->bolo) == 0;
        if (!same_book && bad_book++ < 5)
            print_message("  %s %s: pixel (%d,%d) monitor %.17g/%.17g, %.17g/%.17g, delay "
                          "%.17g/%.17g\n",
                          name, cr_cpu_simd_name(path), k % W, k / W, a->err_mean, b->err_mean,
                          a->err_std, b->err_std, a->delay, b->delay);
        if (!same_class) {
            if ((a->outcome == CR_OUT_DISC || a->outcome == CR_OUT_SPHERE) &&
                a->outcome == b->outcome && pk_rel(a->hit_r, b->hit_r) <= 1e-9 &&
                fabs(a->hit_phi - b->hit_phi) <= 1e-9) {
                edge++;
                print_message("  %s %s: pixel (%d,%d) on a class edge: hit r %.17g, phi %.17g\n",
                              name, cr_cpu_simd_name(path), k % W, k / W, a->hit_r,
                              a->hit_phi);
                continue;
            }
            if (bad++ < 5)
                print_message("  %s %s: pixel (%d,%d) outcome %d/%d object %d/%d colour "
                              "%d,%d,%d/%d,%d,%d\n",
                              name, cr_cpu_simd_name(path), k % W, k / W, a->outcome,
                              b->outcome, a->object, b->object, a->color.r, a->color.g,
                              a->color.b, b->color.r, b->color.g, b->color.b);
            continue;
        }
        worst_g = fmax(worst_g, dg);
        if (dg > 1e-12 || pk_rel(a->bolo, b->bolo) > 1e-12 || pk_rel(a->hit_r, b->hit_r) > 1e-12 ||
            pk_rel(a->hit_phi, b->hit_phi) > 1e-12) {
            if (bad++ < 5)
                print_message("  %s %s: pixel (%d,%d) redshift %.17g/%.17g\n", name,
                              cr_cpu_simd_name(path), k % W, k / W, a->redshift, b->redshift);
        }
        if (a->steps != b->steps && bad_steps++ < 5)
            print_message("  %s %s: pixel (%d,%d) steps %u/%u\n", name, cr_cpu_simd_name(path),
                          k % W, k / W, a->steps, b->steps);
    }
    print_message("%-44s %-16s %4ld of %d pixels equal bit for bit, %ld on an edge, worst "
                  "redshift %.1e, %ld mismatches, %ld steps differ, %ld monitor/delay differ\n",
                  name, cr_cpu_simd_name(path), same_bits, W * H, edge, worst_g, bad, bad_steps,
                  bad_book);
    cr_scene_free(&s);
    return (int)(bad + bad_steps + bad_book);
}

static int pk_compare_scene(const char *name, int path)
{
    return pk_compare_limits(name, path, 0, 0.0, NULL);
}

/* The packet paths this CPU has (AVX2, AVX-512), as CR_CPU_SIMD_* bits. */
static int pk_paths(void)
{
    int p, bits = 0;
    for (p = CR_CPU_SIMD_AVX2; p <= CR_CPU_SIMD_AVX512; p++)
        if (cr_cpu_simd_pick(CR_SIMD_AUTO, 1, p == CR_CPU_SIMD_AVX512) == p &&
            !(p == CR_CPU_SIMD_AVX512 && cr_cpu_simd_path(CR_SIMD_AUTO) != p) &&
            !(p == CR_CPU_SIMD_AVX2 && cr_cpu_simd_path(CR_SIMD_AUTO) == CR_CPU_SIMD_SCALAR))
            bits |= 1 << p;
    return bits;
}

/* The step and turn limits on the packet path: demo.yml with max_steps 6
 * (most rays end as limit by steps) and with max_turns 0.05 (rays near the
 * hole end as limit by turns), the same pixels as the scalar path; each
 * frame must have limit pixels, so that the limits are exercised. */
static void test_packet_limits(void **state)
{
    int p, bits = pk_paths(), failures = 0;
    (void)state;
    if (!cr_cpu_simd_built() || bits == 0) {
        print_message("SKIPPED: no packet path on this CPU or build\n");
        skip();
    }
    for (p = CR_CPU_SIMD_AVX2; p <= CR_CPU_SIMD_AVX512; p++) {
        long n_steps = 0, n_turns = 0;
        if (!(bits & (1 << p)))
            continue;
        failures += pk_compare_limits("demo.yml", p, 6, 0.0, &n_steps);
        failures += pk_compare_limits("demo.yml", p, 0, 0.05, &n_turns);
        print_message("%s: %ld limit pixels at max_steps 6, %ld at max_turns 0.05\n",
                      cr_cpu_simd_name(p), n_steps, n_turns);
        assert_true(n_steps > 0);
        assert_true(n_turns > 0);
    }
    assert_int_equal(failures, 0);
}

/* Science frames (their steps at the finer tolerance, every hit's delay by
 * quadrature) on the packet path: a Keplerian disc from r = 30 M (listing
 * 7.1.1), one from infinity (keplerian-face-on.yml) and a moving sphere
 * (hot-spot-isco.yml), the same pixels as the scalar path. */
static void test_packet_science(void **state)
{
    static const char *const names[3] = {"listing-7.1.1-schwarzschild-disc.yml",
                                         "keplerian-face-on.yml", "hot-spot-isco.yml"};
    int p, i, bits = pk_paths(), failures = 0;
    (void)state;
    if (!cr_cpu_simd_built() || bits == 0) {
        print_message("SKIPPED: no packet path on this CPU or build\n");
        skip();
    }
    pk_science = 1;
    for (p = CR_CPU_SIMD_AVX2; p <= CR_CPU_SIMD_AVX512; p++)
        if (bits & (1 << p))
            for (i = 0; i < 3; i++)
                failures += pk_compare_scene(names[i], p);
    pk_science = 0;
    assert_int_equal(failures, 0);
}

static void test_packet_matches_scalar(void **state)
{
    char dir[1024];
    char **names = NULL;
    int n = 0, i, p, failures = 0, paths = 0;
    DIR *d;
    struct dirent *e;
    (void)state;
    if (!cr_cpu_simd_built()) {
        print_message("SKIPPED: this build has no packet path\n");
        skip();
    }
    snprintf(dir, sizeof dir, "%s/scenes", CR_SOURCE_DIR);
    d = opendir(dir);
    assert_non_null(d);
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len > 4 && strcmp(e->d_name + len - 4, ".yml") == 0) {
            char **g = realloc(names, sizeof *names * (size_t)(n + 1));
            assert_non_null(g);
            names = g;
            names[n] = strdup(e->d_name);
            assert_non_null(names[n]);
            n++;
        }
    }
    closedir(d);
    assert_true(n >= 10);
    qsort(names, (size_t)n, sizeof *names, pk_cmp_str);
    for (p = CR_CPU_SIMD_AVX2; p <= CR_CPU_SIMD_AVX512; p++) {
        /* only the paths this CPU has */
        if (cr_cpu_simd_pick(CR_SIMD_AUTO, 1, p == CR_CPU_SIMD_AVX512) != p ||
            (p == CR_CPU_SIMD_AVX512 && cr_cpu_simd_path(CR_SIMD_AUTO) != p) ||
            (p == CR_CPU_SIMD_AVX2 && cr_cpu_simd_path(CR_SIMD_AUTO) == CR_CPU_SIMD_SCALAR))
            continue;
        paths++;
        for (i = 0; i < n; i++)
            failures += pk_compare_scene(names[i], p);
    }
    for (i = 0; i < n; i++)
        free(names[i]);
    free(names);
    if (paths == 0) {
        print_message("SKIPPED: this CPU has no AVX2\n");
        skip();
    }
    assert_int_equal(failures, 0);
}

/* ---- the dispatch ---------------------------------------------------------- */

static void test_dispatch(void **state)
{
    int built = cr_cpu_simd_built();
    (void)state;
    /* without AVX2 (whatever else), with cpu.simd off: scalar */
    assert_int_equal(cr_cpu_simd_pick(CR_SIMD_AUTO, 0, 0), CR_CPU_SIMD_SCALAR);
    assert_int_equal(cr_cpu_simd_pick(CR_SIMD_AUTO, 0, 1), CR_CPU_SIMD_SCALAR);
    assert_int_equal(cr_cpu_simd_pick(CR_SIMD_OFF, 1, 1), CR_CPU_SIMD_SCALAR);
    assert_int_equal(cr_cpu_simd_pick(CR_SIMD_OFF, 1, 0), CR_CPU_SIMD_SCALAR);
    assert_int_equal(cr_cpu_simd_pick(CR_SIMD_AUTO, 1, 0),
                     built ? CR_CPU_SIMD_AVX2 : CR_CPU_SIMD_SCALAR);
    assert_int_equal(cr_cpu_simd_pick(CR_SIMD_AUTO, 1, 1),
                     built ? CR_CPU_SIMD_AVX512 : CR_CPU_SIMD_SCALAR);
    /* this CPU with its features taken away */
    assert_int_equal(setenv("CURRAY_TEST_CPU_FEATURES", "none", 1), 0);
    assert_int_equal(cr_cpu_simd_path(CR_SIMD_AUTO), CR_CPU_SIMD_SCALAR);
    assert_int_equal(setenv("CURRAY_TEST_CPU_FEATURES", "avx2", 1), 0);
    assert_true(cr_cpu_simd_path(CR_SIMD_AUTO) != CR_CPU_SIMD_AVX512);
    assert_int_equal(cr_cpu_simd_path(CR_SIMD_OFF), CR_CPU_SIMD_SCALAR);
    assert_int_equal(unsetenv("CURRAY_TEST_CPU_FEATURES"), 0);
    assert_string_equal(cr_cpu_simd_name(CR_CPU_SIMD_SCALAR), "scalar");
    assert_string_equal(cr_cpu_simd_name(CR_CPU_SIMD_AVX2), "AVX2, 4 lanes");
    assert_string_equal(cr_cpu_simd_name(CR_CPU_SIMD_AVX512), "AVX-512, 8 lanes");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_early_stop_exact),
        cmocka_unit_test(test_dispatch),
        cmocka_unit_test(test_packet_matches_scalar),
        cmocka_unit_test(test_packet_limits),
        cmocka_unit_test(test_packet_science),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
