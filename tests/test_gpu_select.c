/* GPU selection (cr_gpu_select, src/render/gpu_select.c) with made-up device
 * tables: device numbers are the runtime's, so the number of usable devices
 * is no bound on them (a gpus: entry names any device). Runs in every build, with or
 * without CUDA, and needs no GPU. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "render/gpu.h"

#define N_MAX 8

/* table[d].usable from the string: '1' usable, '0' not (with a reason). */
static int make_table(cr_gpu_device *t, const char *usable)
{
    int d, n = (int)strlen(usable);
    for (d = 0; d < n; d++) {
        t[d].usable = usable[d] == '1';
        snprintf(t[d].why, sizeof t[d].why, "%s",
                 t[d].usable ? "" : "compute capability 3.5; this build runs on 8.0 and up");
    }
    return n;
}

/* enabled[d] from the string of '1'/'0'; returns its length. */
static int make_enabled(int *e, const char *on)
{
    int d, n = (int)strlen(on);
    for (d = 0; d < n; d++)
        e[d] = on[d] == '1';
    return n;
}

/* Run the selection; returns the chosen devices as a string like "1,3". */
static const char *pick(const char *usable, const char *on, int max_chosen, cr_err *err)
{
    static char out[64];
    cr_gpu_device t[N_MAX];
    int e[N_MAX], chosen[N_MAX], n, k;
    int nd = make_table(t, usable), ne = make_enabled(e, on);
    memset(chosen, -1, sizeof chosen);
    n = cr_gpu_select(t, nd, e, ne, chosen, max_chosen, err);
    out[0] = '\0';
    for (k = 0; k < n; k++)
        snprintf(out + strlen(out), sizeof out - strlen(out), "%s%d", k ? "," : "", chosen[k]);
    assert_true(n <= max_chosen);
    return out;
}

static void test_unusable_first(void **state)
{
    cr_err err;
    (void)state;
    /* GPU 0 unusable, GPU 1 usable, both enabled: 1 is chosen, 0 named */
    assert_string_equal(pick("01", "11", N_MAX, &err), "1");
    assert_non_null(strstr(err.msg, "GPU 0 is unusable (compute capability 3.5"));
    /* the same with only device 0 enabled (no gpus section): nothing, and
     * the message points at the usable device 1 */
    assert_string_equal(pick("01", "1", N_MAX, &err), "");
    assert_non_null(strstr(err.msg, "GPU 0 is unusable"));
    assert_non_null(strstr(err.msg, "usable but not enabled in the configuration: 1"));
}

static void test_gaps(void **state)
{
    cr_err err;
    (void)state;
    /* usable 0, 2, 4 of five: the count (3) must not bound the numbers */
    assert_string_equal(pick("10101", "11111", N_MAX, &err), "0,2,4");
    assert_non_null(strstr(err.msg, "GPU 1 is unusable"));
    assert_non_null(strstr(err.msg, "GPU 3 is unusable"));
    assert_string_equal(pick("10101", "00101", N_MAX, &err), "2,4");
    assert_string_equal(err.msg, ""); /* nothing enabled was skipped */
    assert_string_equal(pick("00001", "00001", N_MAX, &err), "4");
    assert_string_equal(pick("11111", "11111", N_MAX, &err), "0,1,2,3,4");
    assert_string_equal(pick("11111", "11111", 2, &err), "0,1"); /* room for two */
}

static void test_none_usable(void **state)
{
    cr_err err;
    (void)state;
    assert_string_equal(pick("00", "11", N_MAX, &err), "");
    assert_non_null(strstr(err.msg, "GPU 0 is unusable"));
    assert_non_null(strstr(err.msg, "GPU 1 is unusable"));
    assert_string_equal(pick("", "11", N_MAX, &err), "");
    assert_string_equal(err.msg, "no CUDA device found");
}

static void test_config_disables(void **state)
{
    cr_err err;
    (void)state;
    assert_string_equal(pick("11", "00", N_MAX, &err), "");
    assert_non_null(strstr(err.msg, "no GPU is enabled in the configuration; usable: 0, 1"));
    assert_string_equal(pick("00", "00", N_MAX, &err), "");
    assert_non_null(strstr(err.msg, "no GPU is enabled in the configuration, and none is usable"));
    /* devices past the end of the enabled list are disabled */
    assert_string_equal(pick("1111", "01", N_MAX, &err), "1");
    assert_string_equal(pick("1111", "", N_MAX, &err), "");
    /* a NULL err is allowed */
    assert_string_equal(pick("01", "11", N_MAX, NULL), "1");
}

/* The GPUs of MPI ranks (cr_gpu_for_local_rank): local rank k of
 * local_size on a node whose selection is `usable`/`on` (as pick() takes
 * them) gets one device each; returns them as "d0,d1,...", and the note of
 * the last rank in *note. */
static const char *ranks(const char *usable, const char *on, int local_size, cr_err *note)
{
    static char out[64];
    cr_gpu_device t[N_MAX];
    int e[N_MAX], chosen[N_MAX], n, k;
    int nd = make_table(t, usable), ne = make_enabled(e, on);
    cr_err err;
    n = cr_gpu_select(t, nd, e, ne, chosen, N_MAX, &err);
    out[0] = '\0';
    for (k = 0; k < local_size; k++)
        snprintf(out + strlen(out), sizeof out - strlen(out), "%s%d", k ? "," : "",
                 cr_gpu_for_local_rank(chosen, n, k, local_size, note));
    return out;
}

static void test_local_rank(void **state)
{
    cr_err note;
    int one = 0;
    (void)state;
    /* 2 ranks, 1 GPU: both trace on device 0 (shared, no CPU fallback) */
    assert_string_equal(ranks("1", "1", 2, &note), "0,0");
    assert_non_null(strstr(note.msg, "2 MPI ranks on this node share its 1 usable GPU"));
    /* 4 ranks, 2 GPUs: round robin */
    assert_string_equal(ranks("11", "11", 4, &note), "0,1,0,1");
    assert_non_null(strstr(note.msg, "share its 2 usable GPUs"));
    /* GPU 0 unusable: the ranks take the usable ones by their numbers */
    assert_string_equal(ranks("011", "111", 4, &note), "1,2,1,2");
    assert_string_equal(ranks("01", "11", 2, &note), "1,1");
    /* as many ranks as GPUs: one each, nothing to say */
    assert_string_equal(ranks("1111", "1111", 4, &note), "0,1,2,3");
    assert_string_equal(note.msg, "");
    /* fewer ranks than GPUs: the rest stay idle, and the note says so */
    assert_string_equal(ranks("1111", "1111", 3, &note), "0,1,2");
    assert_non_null(strstr(note.msg, "4 usable GPUs on this node but 3 MPI ranks: 1 GPU stays "
                                     "idle"));
    /* disabled in the configuration: skipped like unusable ones */
    assert_string_equal(ranks("111", "101", 3, &note), "0,2,0");
    /* no usable GPU, or a bad rank: -1 (the caller uses the CPU or refuses) */
    assert_string_equal(ranks("0", "1", 2, &note), "-1,-1");
    assert_int_equal(cr_gpu_for_local_rank(&one, 1, -1, 1, &note), -1);
    assert_int_equal(cr_gpu_for_local_rank(NULL, 1, 0, 1, NULL), -1);
    assert_int_equal(cr_gpu_for_local_rank(&one, 1, 0, 1, NULL), 0);
}

/* This build's device table: without a GPU (or without CUDA) no device and
 * a reason; with one, every entry described. */
static void test_devices_of_this_build(void **state)
{
    cr_gpu_device t[64];
    cr_err err;
    int n, d;
    (void)state;
    err.msg[0] = '\0';
    n = cr_gpu_devices(t, 64, &err);
    printf("this build sees %d CUDA device%s%s%s\n", n, n == 1 ? "" : "s", n ? "" : ": ",
           n ? "" : err.msg);
    if (n == 0) {
        assert_true(err.msg[0] != '\0');
        assert_int_equal(cr_gpu_built() ? 1 : 0, cr_gpu_built());
    }
    for (d = 0; d < n && d < 64; d++)
        assert_true(t[d].usable || t[d].why[0]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unusable_first),
        cmocka_unit_test(test_gaps),
        cmocka_unit_test(test_none_usable),
        cmocka_unit_test(test_config_disables),
        cmocka_unit_test(test_local_rank),
        cmocka_unit_test(test_devices_of_this_build),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
