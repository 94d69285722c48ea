/* The command line's pure parts (src/cli/cli.c): the prompt's answer and
 * the --threads limit (the one limit, CR_SYSCONFIG_MAX_THREADS, also used
 * by the configuration and the CPU backend). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "cli/cli.h"
#include "input/sysconfig.h"

static void test_answer(void **state)
{
    (void)state;
    assert_true(cr_cli_answer_yes("\n"));
    assert_true(cr_cli_answer_yes(""));
    assert_true(cr_cli_answer_yes("y\n"));
    assert_true(cr_cli_answer_yes("Y\n"));
    assert_true(cr_cli_answer_yes("yes\n"));
    assert_true(cr_cli_answer_yes(" y\n"));    /* a leading space used to decline */
    assert_true(cr_cli_answer_yes("\t yes \n"));
    assert_true(cr_cli_answer_yes("   \n"));
    assert_false(cr_cli_answer_yes("n\n"));
    assert_false(cr_cli_answer_yes(" n\n"));
    assert_false(cr_cli_answer_yes("no\n"));
    assert_false(cr_cli_answer_yes("q\n"));
}

static int parse_threads(const char *value, cr_cli *c, cr_err *err)
{
    char *argv[] = {"curray", "--threads", (char *)value, NULL};
    return cr_cli_parse(3, argv, 0, c, err);
}

static void test_threads_limit(void **state)
{
    cr_cli c;
    cr_err err;
    char max[32], over[32], want[160];
    (void)state;
    snprintf(max, sizeof max, "%d", CR_SYSCONFIG_MAX_THREADS);
    snprintf(over, sizeof over, "%d", CR_SYSCONFIG_MAX_THREADS + 1);
    assert_int_equal(parse_threads(max, &c, &err), 0);
    assert_int_equal(c.threads, CR_SYSCONFIG_MAX_THREADS);
    assert_int_equal(parse_threads(over, &c, &err), -1);
    snprintf(want, sizeof want, "--threads: expected a number of threads from 1 to %d, got '%s'",
             CR_SYSCONFIG_MAX_THREADS, over);
    assert_string_equal(err.msg, want);
    assert_int_equal(parse_threads("0", &c, &err), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_answer),
        cmocka_unit_test(test_threads_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
