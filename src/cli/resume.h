/* curray cli: what an output folder already holds (--resume, stale files).
 *
 * - Frame files: c_<k>.png, r_<k>.png, d_<k>.csv (cr_output_file_name). The
 *   names keep the paper's unpadded k.
 * - Stale files: frame files that this run will not overwrite (a frame
 *   number >= the run's frame count, or a type the run does not write).
 *   They are reported, never deleted.
 * - The run hash: FNV-1a 64 of everything that decides the bytes of the
 *   outputs (scene file and sky image bytes, the raytracer settings, size,
 *   frame count, output types, video settings, CPU or CUDA). info.txt
 *   carries it; --resume refuses a folder whose hash differs.
 * - Resume: the records of the frames an earlier run finished, read back
 *   from its info.txt (info.h), so that a resumed run can keep them. Each
 *   record lists its files with their sizes and CRC-32s; a frame is kept
 *   only when every file still matches. */
#ifndef CR_CLI_RESUME_H
#define CR_CLI_RESUME_H

#include <stddef.h>

#include "../base/error.h"
#include "../input/scene.h"
#include "../input/sysconfig.h"

/* Scan dir for frame files this run will not overwrite (frames, types: the
 * run's). *text gets a one-line description, malloc'ed ("c_<k>.png for
 * k = 4-7; d_<k>.csv for k = 0"), or NULL when there are none (or dir does
 * not exist). Returns how many files, or -1 when out of memory. */
int cr_stale_scan(const char *dir, int frames, const char *types, char **text);

/* Remove the temporary files ".<name>.tmp.<pid>.*" that a killed curray
 * (a pid that no longer runs) left in dir. Returns how many were removed. */
int cr_remove_dead_temps(const char *dir);

/* The run hash as 16 hex digits (plus NUL) in out. types: the output types
 * (order does not matter). extra: further settings text that changes the
 * outputs (video settings), may be "". */
int cr_run_hash(const cr_scene *scene, const cr_sysconfig *cfg, long width, long height,
                long frames, const char *types, int use_cuda, const char *extra, char out[17],
                cr_err *err);

/* dir/info.txt is a folder (which info.txt cannot replace): -1 with err
 * naming it, before anything is rendered; else 0. */
int cr_info_path_check(const char *dir, cr_err *err);

/* The frames an earlier run finished, from dir/info.txt. */
typedef struct cr_resume {
    int frames;     /* the run's frame count */
    int n_records;  /* records kept from the file, in its order */
    int *order;     /* order[i]: frame of the i-th record */
    char **body;    /* body[k]: frame k's record without its "Finished" line,
                       or NULL when the file has none */
    char started[64]; /* the earlier run's "Started" time */
    char why[512];    /* cr_resume_verify: what the first frame dropped did not match */
} cr_resume;

/* Read dir/info.txt and check that its run hash equals hash. Errors: no
 * info.txt ("no earlier run"), no hash line, another hash (the scene,
 * configuration, size or options changed). */
int cr_resume_load(cr_resume *r, const char *dir, const char *hash, int frames, cr_err *err);

/* The lines that end frame k's record in info.txt, one per file of the
 * frame's types (among "crdbf") in dir, each with its size and CRC-32:
 * "  frame file             c_3.png 123456 bytes, crc32 0a1b2c3d\n". *text
 * is malloc'ed (NULL when types is empty). Reads each file back: call it
 * once the frame's files are all written. */
int cr_frame_files_describe(const char *dir, int k, const char *types, char **text, cr_err *err);

/* Check the files (types among "crdbf") of every kept frame against the
 * size and CRC-32 in its record; drop the records of frames whose files do
 * not match (missing, another size or checksum, a symbolic link, not a
 * regular file, no size and checksum recorded): they are rendered again.
 * Returns how many were dropped (r->why says what was wrong with the first),
 * or -1 with err set when a frame's file name is taken by a folder. Linear
 * in the records and the bytes of the kept files. */
int cr_resume_verify(cr_resume *r, const char *dir, const char *types, cr_err *err);

void cr_resume_free(cr_resume *r);

#endif
