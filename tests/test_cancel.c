/* The CPU backend's cancel flag (Ctrl-C stops a render within a pixel) and
 * thread limit:
 * - a C11 atomic_int checked per pixel: cancelling a render of one
 *   65,536-pixel row near the hole returns within 0.2 s (a check between rows
 *   only would finish the whole row, many seconds);
 * - a cancelled render returns -1 "interrupted"; a NULL flag never cancels;
 * - more threads than CR_SYSCONFIG_MAX_THREADS is an error, not a clamp.
 * Threaded: run under ThreadSanitizer by .ci/run. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "render/cpu.h"
#include "testutil.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct job {
    cr_frame f;
    cr_pixel *px;
    atomic_int cancel;
    int rc;
    cr_err err;
    double t_end;
} job;

static void *render_thread(void *arg)
{
    job *j = arg;
    j->rc = cr_cpu_render(&j->f, 2, j->px, NULL, NULL, &j->cancel, &j->err);
    j->t_end = now_s();
    return NULL;
}

static void test_cancel_within_a_row(void **state)
{
    job *j = calloc(1, sizeof *j);
    pthread_t tid;
    double t_cancel, waited;
    (void)state;
    assert_non_null(j);
    /* one row of 65,536 pixels, observer at r = 3.5 M next to the photon
     * sphere of a Kerr hole, the paper's RK4 (thousands of steps a ray): the
     * row takes one worker many seconds (12 s measured on the 2-core development machine) */
    cr_test_empty_frame(&j->f, 1.0, 0.9, 0.0, 3.5, 0.5 * CR_PI);
    j->f.integrator = CR_INTEG_RK4;
    j->f.width = 65536;
    j->f.height = 1;
    cr_frame_prepare(&j->f);
    j->px = malloc(sizeof *j->px * 65536);
    assert_non_null(j->px);
    atomic_init(&j->cancel, 0);
    assert_int_equal(pthread_create(&tid, NULL, render_thread, j), 0);
    struct timespec nap = {0, 300 * 1000 * 1000};
    nanosleep(&nap, NULL);
    t_cancel = now_s();
    atomic_store(&j->cancel, 1);
    pthread_join(tid, NULL);
    waited = j->t_end - t_cancel;
    printf("stopped %.3f s after the cancel flag was set\n", waited);
    assert_int_equal(j->rc, -1);
    assert_string_equal(j->err.msg, "interrupted");
    assert_true(waited >= 0.0 && waited < 0.2);
    free(j->px);
    free(j);
}

static void test_no_flag_finishes(void **state)
{
    cr_frame f;
    cr_pixel px[16 * 16];
    cr_err err;
    atomic_int zero;
    (void)state;
    cr_test_empty_frame(&f, 1.0, 0.0, 0.0, 20.0, 0.5 * CR_PI);
    f.width = f.height = 16;
    cr_frame_prepare(&f);
    assert_int_equal(cr_cpu_render(&f, 3, px, NULL, NULL, NULL, &err), 0);
    atomic_init(&zero, 0);
    assert_int_equal(cr_cpu_render(&f, 3, px, NULL, NULL, &zero, &err), 0);
    /* a flag already set: nothing is traced */
    atomic_store(&zero, 1);
    assert_int_equal(cr_cpu_render(&f, 3, px, NULL, NULL, &zero, &err), -1);
    assert_string_equal(err.msg, "interrupted");
}

static void test_thread_limit(void **state)
{
    cr_frame f;
    cr_pixel px[4 * 4];
    cr_err err;
    char want[128];
    (void)state;
    cr_test_empty_frame(&f, 1.0, 0.0, 0.0, 20.0, 0.5 * CR_PI);
    f.width = f.height = 4;
    cr_frame_prepare(&f);
    err.msg[0] = '\0';
    assert_int_equal(cr_cpu_render(&f, CR_SYSCONFIG_MAX_THREADS + 1, px, NULL, NULL, NULL, &err),
                     -1);
    snprintf(want, sizeof want, "%d CPU threads asked for; curray runs at most %d",
             CR_SYSCONFIG_MAX_THREADS + 1, CR_SYSCONFIG_MAX_THREADS);
    assert_string_equal(err.msg, want);
    /* the limit itself is accepted (only 4 rows: 4 threads start) */
    assert_int_equal(cr_cpu_render(&f, CR_SYSCONFIG_MAX_THREADS, px, NULL, NULL, NULL, &err), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cancel_within_a_row),
        cmocka_unit_test(test_no_flag_finishes),
        cmocka_unit_test(test_thread_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
