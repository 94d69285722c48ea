/* curray output: the output types of -t, one table (types.c).
 *
 * Each type is one row: its letter, its file name, whether it is written per
 * frame or once per run, and, per frame, its writer. Everything that asks
 * about output types asks this table: the check of -t (cr_output_types_check),
 * the per-frame files of a run (cr_output_frame_letters), their names
 * (cr_output_file_name: "<letter>_<k>.<ext>", the paper's unpadded k), the
 * writing of a frame (cr_output_type_find(letter)->write), stale files and
 * --resume.
 *
 * A new per-frame type is one row in types.c plus its writer, a function
 * int writer(const cr_frame_output *o, cr_err *err) that writes the file
 * cr_output_file_name names, atomically (atomic.h), and leaves nothing
 * behind on failure. The per-run types (info.txt, videos) have their own
 * life cycle (info.h, video.h); their rows carry the letter and file name. */
#ifndef CR_OUTPUT_TYPES_H
#define CR_OUTPUT_TYPES_H

#include <stddef.h>

#include "../core/defs.h"
#include "../base/error.h"
#include "../input/scene.h"

/* What a per-frame writer is given: frame k of n, as traced. */
typedef struct cr_frame_output {
    const char *dir;        /* the output folder */
    int k, n;               /* frame k of a run of n frames */
    const cr_frame *frame;  /* the frame that was traced (lengths in units of M);
                               its width x height are the image's */
    const cr_pixel *px;     /* frame->width x frame->height pixels, row 0 at
                               the top, as traced from frame */
    const cr_scene *scene;  /* what the frame was made from, for what the frame
                               does not hold: the scene file's name, M in the
                               scene's length unit, the key redshift_sky */
    char *note;             /* NULL, or room for note_n bytes where a writer puts a
                               warning for the console ("" when none) */
    size_t note_n;
} cr_frame_output;

typedef enum cr_output_scope {
    CR_OUTPUT_PER_FRAME, /* one file per frame: <letter>_<k>.<file> */
    CR_OUTPUT_PER_RUN    /* one file (or two) per run, named by file */
} cr_output_scope;

typedef struct cr_output_type {
    char letter;            /* as -t spells it */
    cr_output_scope scope;
    const char *file;       /* per frame: the extension ("png"); per run: the
                               file name ("info.txt") */
    /* per frame: write o's file of this type; returns 0, or -1 with err set
       and no file left behind. NULL for the per-run types. */
    int (*write)(const cr_frame_output *o, cr_err *err);
    char implies;           /* another type this one needs written too (the
                               video v is made from the colour frames c), or 0 */
    /* NULL when always available; else 1 when this build writes the type
       (a loadable module is loaded by it), or 0 with err set to the message
       -t gets; unavailable: the message when available() sets none */
    int (*available)(cr_err *err);
    const char *unavailable;
} cr_output_type;

/* The row of letter t, or NULL when t is no output type. */
const cr_output_type *cr_output_type_find(char t);

/* The i-th row (0 <= i < cr_output_type_count()), in table order. */
const cr_output_type *cr_output_type_at(int i);
int cr_output_type_count(void);

/* Check a -t value: not empty, every letter an output type this build can
 * write. Returns 0, or -1 with the message for -t. */
int cr_output_types_check(const char *types, cr_err *err);

/* Does the set of letters types write type t, itself or as implied by
 * another of its types (v implies c)? */
int cr_output_types_has(const char *types, char t);

/* The per-frame types that types writes (with the implied ones), once each,
 * in table order, into out (NUL-terminated; n > the number of types is
 * enough). */
void cr_output_frame_letters(const char *types, char *out, size_t n);

/* The file name of frame k's output of type t ("c_3.png") into out[n];
 * returns 0, or -1 when t has no per-frame file (i, v) or n is too small. */
int cr_output_file_name(char t, int k, char *out, size_t n);

#endif
