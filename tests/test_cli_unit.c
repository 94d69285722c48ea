/* The command line's pure parts (src/cli/cli.c): the prompt's answer, the
 * --threads limit (the one limit, CR_SYSCONFIG_MAX_THREADS, also used by the
 * configuration and the CPU backend), the values of -v, -q and -a, and
 * parsing twice in one process. */
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

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

/* A fake environment for cr_cli_mpi_launched: "NAME=value" pairs. */
static const char *const *fake_env;
static const char *fake_getenv(const char *name)
{
    size_t n = strlen(name);
    for (const char *const *e = fake_env; *e; e++)
        if (strncmp(*e, name, n) == 0 && (*e)[n] == '=')
            return *e + n + 1;
    return NULL;
}

static int launched(const char *const *env, char *why)
{
    fake_env = env;
    why[0] = '\0';
    return cr_cli_mpi_launched(fake_getenv, why, 96);
}

/* Started by an MPI launcher as one of several processes: the size from
 * Open MPI, MPICH/Intel/srun PMI or MVAPICH2, or a rank above 0 alone. */
static void test_mpi_launched(void **state)
{
    char why[96];
    (void)state;
    assert_int_equal(launched((const char *const[]){NULL}, why), 0);
    assert_int_equal(launched((const char *const[]){"OMPI_COMM_WORLD_SIZE=1", NULL}, why), 0);
    assert_int_equal(launched((const char *const[]){"OMPI_COMM_WORLD_SIZE=4", NULL}, why), 4);
    assert_string_equal(why, "OMPI_COMM_WORLD_SIZE=4");
    assert_int_equal(launched((const char *const[]){"PMI_SIZE=2", "PMI_RANK=1", NULL}, why), 2);
    assert_string_equal(why, "PMI_SIZE=2");
    assert_int_equal(launched((const char *const[]){"MV2_COMM_WORLD_SIZE=3", NULL}, why), 3);
    assert_int_equal(launched((const char *const[]){"PMIX_RANK=0", NULL}, why), 0);
    assert_int_equal(launched((const char *const[]){"PMIX_RANK=5", NULL}, why), -1);
    assert_string_equal(why, "PMIX_RANK=5");
    assert_int_equal(launched((const char *const[]){"PMI_SIZE=1", "PMI_RANK=0", NULL}, why), 0);
    /* not numbers: not a launcher's */
    assert_int_equal(launched((const char *const[]){"PMI_SIZE=", "OMPI_COMM_WORLD_SIZE=x2",
                                                     "PMIX_RANK=-3", NULL},
                              why),
                     0);
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

/* A parse that does not return within the alarm is a failure, not a hang. */
static void on_alarm(int sig)
{
    static const char msg[] = "test_cli_unit: cr_cli_parse did not return within 10 s\n";
    (void)sig;
    if (write(2, msg, sizeof msg - 1) < 0)
        _exit(1);
    _exit(1);
}

/* Parses argv (NULL-terminated, argv[0] included) under a 10 s alarm. */
static int parse_words(char **argv, cr_cli *c, cr_err *err)
{
    int argc = 0, rc;
    while (argv[argc])
        argc++;
    signal(SIGALRM, on_alarm);
    alarm(10);
    rc = cr_cli_parse(argc, argv, 0, c, err);
    alarm(0);
    return rc;
}

/* A value glued to -v, -q or -a ("-q-a", "--verbose=-x") is that option's
 * value: a word that is not true or false is refused with the option's
 * message. Stepping back over it as over a separate word re-read the same
 * word forever. */
static void test_glued_value(void **state)
{
    static const struct {
        const char *word, *msg;
    } cases[] = {
        {"-q-a", "-q: expected true or false, got '-a'"},
        {"-v-1", "-v: expected true or false, got '-1'"},
        {"-a-q", "-a: expected true or false, got '-q'"},
        {"--verbose=-x", "-v: expected true or false, got '-x'"},
        {"--quiet=-", "-q: expected true or false, got '-'"},
        {"--auto_accept=--", "-a: expected true or false, got '--'"},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *argv[] = {"curray", "-s", "ok.yml", (char *)cases[i].word, "-o", "o", NULL};
        cr_cli c;
        cr_err err;
        err.msg[0] = '\0';
        assert_int_equal(parse_words(argv, &c, &err), -1);
        assert_string_equal(err.msg, cases[i].msg);
    }
}

/* The values that do parse: glued, separate, bare before another option and
 * bare at the end. */
static void test_bool_values(void **state)
{
    cr_cli c;
    cr_err err;
    (void)state;
    {
        char *argv[] = {"curray", "-qtrue", "--verbose=no", "-a", "on", NULL};
        assert_int_equal(parse_words(argv, &c, &err), 0);
        assert_int_equal(c.quiet, 1);
        assert_int_equal(c.verbose, 0);
        assert_int_equal(c.auto_accept, 1);
    }
    {
        char *argv[] = {"curray", "-q", "-a", "-s", "x.yml", "-v", NULL};
        assert_int_equal(parse_words(argv, &c, &err), 0);
        assert_int_equal(c.quiet, 1);
        assert_int_equal(c.auto_accept, 1);
        assert_int_equal(c.verbose, 1);
        assert_string_equal(c.scene_path, "x.yml");
    }
    {
        char *argv[] = {"curray", "-v", "-1", NULL};
        assert_int_equal(parse_words(argv, &c, &err), -1);
        assert_string_equal(err.msg, "unknown option -1 (see -h)");
    }
}

/* A parse that stopped inside a word of clustered options ("-Zi") leaves
 * nothing behind for the next parse: the "i" of the old words is not read. */
static void test_parse_twice(void **state)
{
    char first[] = "-Zi";
    char *argv1[] = {"curray", first, NULL};
    char *argv2[] = {"curray", "-s", "x.yml", NULL};
    cr_cli c;
    cr_err err;
    (void)state;
    assert_int_equal(parse_words(argv1, &c, &err), -1);
    assert_string_equal(err.msg, "unknown option -Z (see -h)");
    assert_int_equal(parse_words(argv2, &c, &err), 0);
    assert_int_equal(c.info, 0);
    assert_string_equal(c.scene_path, "x.yml");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_answer),
        cmocka_unit_test(test_mpi_launched),
        cmocka_unit_test(test_threads_limit),
        cmocka_unit_test(test_glued_value),
        cmocka_unit_test(test_bool_values),
        cmocka_unit_test(test_parse_twice),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
