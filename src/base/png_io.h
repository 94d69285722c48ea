/* curray io: PNG files through libpng. */
#ifndef CR_IO_PNG_IO_H
#define CR_IO_PNG_IO_H

#include <stdint.h>

#include "error.h"

/* Write an 8-bit RGB image (rgb[3 * (y * w + x)], row 0 at the top)
 * atomically: to a temporary name in the same folder, then renamed, so that
 * a failure or interruption never leaves a truncated file at path. */
int cr_png_write(const char *path, int w, int h, const uint8_t *rgb, cr_err *err);

/* The same with a zlib compression level 0..9 (cr_png_write uses 6, a good
 * trade of speed for size; 9 for files kept in the repository). */
int cr_png_write_level(const char *path, int w, int h, const uint8_t *rgb, int level,
                       cr_err *err);

/* A read with a pixel limit (a sky image) refuses an image that decodes to
 * more than CR_PNG_BOMB_BYTES and more than CR_PNG_MAX_RATIO times its
 * file's size: a decompression bomb (the shipped sky_grid.png, lines on
 * black, is 254 times; a photograph 5 to 20). */
#define CR_PNG_MAX_RATIO 500.0
#define CR_PNG_BOMB_BYTES (256.0 * 1024.0 * 1024.0)

/* Read any PNG (grey, palette, alpha, 16-bit, interlaced) as 8-bit RGB into a
 * malloc'ed buffer. Refuses, before allocating, an image of more than
 * max_pixels pixels (naming its size; max_pixels <= 0: no limit), one whose
 * decoded pixels do not fit in memory (memcheck.h), and with max_pixels > 0
 * a decompression bomb (above). Errors name
 * the file and the cause (missing, not a PNG, truncated, ...). Alpha is
 * composited against black; 16-bit samples are rounded to 8 bits. */
int cr_png_read(const char *path, long long max_pixels, uint8_t **rgb, int *w, int *h,
                cr_err *err);

#endif
