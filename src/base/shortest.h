/* curray base: the shortest decimal text of a double that reads back as the
 * same double.
 *
 * cr_shortest_double writes the decimal with the fewest significant digits
 * that strtod (round to nearest) turns back into exactly v, and of those the
 * one closest to v (ties: even last digit). Digits come from Giulietti's
 * Schubfach algorithm ("The Schubfach way to render doubles", 2020; the
 * algorithm of Java's Double.toString since JDK 19), written here from the
 * paper with a table of 128-bit powers of ten (shortest_table.h, generated
 * exactly by tools/gen-shortest-table.py).
 *
 * Layout as printf's %g would choose it at precision 17: plain notation
 * ("0.0123", "-45", "12345.5") when the decimal exponent X of the first digit
 * is -5 < X < 17, otherwise d.ddde+XX ("1e-05", "6.02214076e+23", exponent
 * with a sign and at least two digits). Zero is "0" or "-0"; infinities and
 * NaN as printf's %g writes them ("inf", "-inf", "nan", "-nan"). */
#ifndef CR_BASE_SHORTEST_H
#define CR_BASE_SHORTEST_H

/* Room that cr_shortest_double needs, NUL included ("-2.2250738585072014e-308"
 * is 24 characters). */
#define CR_SHORTEST_MAX 32

/* Write v into out (CR_SHORTEST_MAX bytes) and NUL-terminate it; returns the
 * length without the NUL. */
int cr_shortest_double(char *out, double v);

#endif
