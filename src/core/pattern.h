/* curray core: colours and the chessboard pattern the disc and the spheres
 * are painted with (E.4).
 */
#ifndef CR_CORE_PATTERN_H
#define CR_CORE_PATTERN_H

#include "defs.h"

/* Chessboard grey between accent squares. */
#define CR_GREY_LEVEL 128

CR_HD static inline cr_rgb cr_rgb_make(int r, int g, int b)
{
    cr_rgb c;
    c.r = (uint8_t)r;
    c.g = (uint8_t)g;
    c.b = (uint8_t)b;
    return c;
}

/* Chessboard: square (i, j) takes the accent colour when i + j is even. */
CR_HD static inline cr_rgb cr_chess(int i, int j, cr_rgb accent)
{
    return ((i + j) & 1) ? cr_rgb_make(CR_GREY_LEVEL, CR_GREY_LEVEL, CR_GREY_LEVEL) : accent;
}

/* Index of x in n equal bins of [0, 1), clamped to 0..n-1. */
CR_HD static inline int cr_bin(double x, int n)
{
    int i = (int)floor(x * n);
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

#endif
