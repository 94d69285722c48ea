/* The names table (input/names.h): one word per value of each enumeration.
 *
 * - every word parses back to its value, and the list for messages is the
 *   words in value order joined by ", ";
 * - the words the formats have always taken, value by value (a renamed or
 *   reordered word would change files and messages);
 * - values without a word and text that is no word: "unknown" and -1;
 * - cr_integrator_parse folds case and trims blanks, cr_name_parse does
 *   neither (scene words are exact).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "core/defs.h"
#include "input/names.h"

static void test_round_trip(void **state)
{
    (void)state;
    for (int kind = 0; kind < CR_NAMES_COUNT_; kind++) {
        char list[512] = "";
        int n = cr_names_count((cr_names)kind);
        assert_true(n >= 2);
        for (int v = 0; v < n; v++) {
            const char *w = cr_name((cr_names)kind, v);
            assert_string_not_equal(w, "unknown");
            assert_int_equal(cr_name_parse((cr_names)kind, w, strlen(w)), v);
            strcat(list, v ? ", " : "");
            strcat(list, w);
        }
        assert_string_equal(cr_names_list((cr_names)kind), list);
        assert_string_equal(cr_name((cr_names)kind, n), "unknown");
        assert_string_equal(cr_name((cr_names)kind, -1), "unknown");
        assert_int_equal(cr_name_parse((cr_names)kind, "", 0), -1);
    }
    assert_string_equal(cr_name(CR_NAMES_COUNT_, 0), "unknown");
    assert_int_equal(cr_name_parse(CR_NAMES_COUNT_, "mino", 4), -1);
    assert_string_equal(cr_names_list(CR_NAMES_COUNT_), "");
}

static void test_words(void **state)
{
    (void)state;
    assert_string_equal(cr_names_list(CR_NAMES_MOTION), "static, zamo, orbit, infall");
    assert_int_equal(cr_names_count(CR_NAMES_MOTION), CR_MOTION_VELOCITY);
    assert_string_equal(cr_name(CR_NAMES_MOTION, CR_MOTION_ORBIT), "orbit");
    assert_string_equal(cr_name(CR_NAMES_MOTION, CR_MOTION_VELOCITY), "unknown");
    assert_string_equal(cr_names_list(CR_NAMES_PROJECTION),
                        "rectilinear, fisheye, equirectangular");
    assert_string_equal(cr_name(CR_NAMES_PROJECTION, CR_PROJ_EQUIRECT), "equirectangular");
    assert_string_equal(cr_names_list(CR_NAMES_INTEGRATOR), "mino, rk4");
    assert_string_equal(cr_integrator_names(), "mino, rk4");
    assert_string_equal(cr_integrator_name(CR_INTEG_RK4), "rk4");
    assert_string_equal(cr_names_list(CR_NAMES_DISC_MODEL), "chessboard, keplerian");
    assert_string_equal(cr_name(CR_NAMES_DISC_MODEL, CR_DISC_KEPLERIAN), "keplerian");
    assert_string_equal(cr_names_list(CR_NAMES_INSIDE_ISCO), "nothing, plunging");
    assert_string_equal(cr_names_list(CR_NAMES_OUTCOME),
                        "none, horizon, disc, sphere, sky, error, limit, outside, other side, "
                        "singularity");
    assert_int_equal(cr_names_count(CR_NAMES_OUTCOME), CR_OUT_COUNT_);
    assert_string_equal(cr_outcome_name(CR_OUT_LIMIT), "limit");
    assert_string_equal(cr_outcome_name(CR_OUT_COUNT_), "unknown");
}

static void test_exact_and_folded(void **state)
{
    (void)state;
    assert_int_equal(cr_name_parse(CR_NAMES_MOTION, "Zamo", 4), -1);
    assert_int_equal(cr_name_parse(CR_NAMES_MOTION, " zamo", 5), -1);
    assert_int_equal(cr_name_parse(CR_NAMES_MOTION, "zamox", 4), CR_MOTION_ZAMO);
    assert_int_equal(cr_name_parse(CR_NAMES_MOTION, "zam", 3), -1);
    assert_int_equal(cr_integrator_parse(" RK4\t", 5), CR_INTEG_RK4);
    assert_int_equal(cr_integrator_parse("Mino", 4), CR_INTEG_MINO);
    assert_int_equal(cr_integrator_parse("minominominominomino", 20), -1);
    assert_int_equal(cr_integrator_parse("  ", 2), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_words),
        cmocka_unit_test(test_exact_and_folded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
