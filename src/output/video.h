/* curray io: a video of a run's frames (output type v).
 *
 * An MP4 file (H.264, yuv420p, the constant frame rate fps) is made from the
 * PNG frames dir/<prefix>_0.png ... dir/<prefix>_<n-1>.png after they are
 * all written, with FFmpeg's libraries (libavformat, libavcodec, libswscale;
 * no external program). H.264 in yuv420p needs an even width and height: an
 * odd side is padded by one row or column that repeats the last one, so the
 * video is the frame plus at most one pixel. The file is written atomically
 * (atomic.h): a temporary name, renamed when complete.
 *
 * With FFmpeg found, the CMake build makes this file a module,
 * curray_video.so (module.h), that the program loads only when a run writes
 * a video (CURRAY_VIDEO_MODULE_HOST: the program's side, which loads it;
 * CURRAY_VIDEO_MODULE: the module's), or links it in (static builds).
 * Builds without FFmpeg's development files (CURRAY_HAVE_FFMPEG undefined)
 * get a version whose cr_video_available() is 0 and whose
 * cr_video_from_pngs() fails with CR_VIDEO_UNAVAILABLE. */
#ifndef CR_IO_VIDEO_H
#define CR_IO_VIDEO_H

#include <stdatomic.h>

#include "../base/error.h"
#include "../base/limits.h" /* CR_VIDEO_MAX_FPS */

#define CR_VIDEO_UNAVAILABLE                                                                   \
    "this curray was built without FFmpeg's libraries, so it cannot write videos (-t v); "     \
    "install them (Debian: apt-get install libavcodec-dev libavformat-dev libswscale-dev "     \
    "libavutil-dev, or tools/install-deps.sh) and build again"


/* 1 when this build writes videos (FFmpeg linked in, or curray_video.so
 * loaded: the first call loads it); else 0 with err (may be NULL) set to
 * the message -t v gets: "-t v: " and CR_VIDEO_UNAVAILABLE, or why the
 * module cannot be loaded (naming it and the library missing). */
int cr_video_available(cr_err *err);

/* Write dir/name from the n frames dir/<prefix>_<k>.png at fps frames per
 * second (1..CR_VIDEO_MAX_FPS). *padded (may be NULL) is set to 1 when the
 * frame size was odd and padded to even. Every frame must have the size of
 * frame 0. cancel (may be NULL) is read before every frame (relaxed atomic
 * load): once it is > 0 the video stops with err "interrupted". Returns 0,
 * or -1 with err set and no file (nor temporary) left. */
int cr_video_from_pngs(const char *dir, const char *prefix, int n, int fps, const char *name,
                       int *padded, atomic_int *cancel, cr_err *err);

#endif
