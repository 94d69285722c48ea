/* curray output: loadable output modules.
 *
 * The writers that need large libraries are built apart, as modules that
 * curray loads (dlopen) only when a run asks for their output type:
 *   curray_video.so  video.c with FFmpeg's libraries   (-t v)
 *   curray_fits.so   fits.c with cfitsio               (-t f)
 * so a run that writes neither maps none of those libraries (FFmpeg's bring
 * about 140 shared objects, whose loading used to be most of the CPU time of
 * a small frame). The CMake build makes them when it finds the libraries
 * (CURRAY_OUTPUT_MODULES=ON, the default); a static build (CURRAY_STATIC) or
 * CURRAY_OUTPUT_MODULES=OFF links the writers into the program instead, and
 * then nothing here is used.
 *
 * Where a module is looked for, in this order, the first file found wins:
 *   $CURRAY_MODULE_DIR, when set and not empty (then nowhere else);
 *   <folder of the running program>/CURRAY_MODULE_RELDIR, the installed
 *     layout (cmake --install: bin/curray and lib/curray/);
 *   the folder of the running program itself (the build folder).
 * A module is loaded once per process and stays loaded (thread-safe).
 *
 * A module exports one function, its entry, returning a table that begins
 * with a cr_module_header; a module made by another build of curray (another
 * version, or other sizes of the structures passed to it) is refused. */
#ifndef CR_OUTPUT_MODULE_H
#define CR_OUTPUT_MODULE_H

#include "../base/error.h"
#include "../core/defs.h"
#include "../input/scene.h"

/* The folder of the modules relative to the program's (CMake sets it from
 * the install folders, e.g. "../lib/curray"). */
#ifndef CURRAY_MODULE_RELDIR
#define CURRAY_MODULE_RELDIR "../lib/curray"
#endif

/* The file name ending of a module (CMake's CMAKE_SHARED_MODULE_SUFFIX). */
#ifndef CURRAY_MODULE_SUFFIX
#define CURRAY_MODULE_SUFFIX ".so"
#endif

/* What both sides must agree on: the sizes of the structures that cross. */
#define CR_MODULE_LAYOUT                                                                         \
    ((((unsigned long)sizeof(cr_frame) * 1009ul + (unsigned long)sizeof(cr_pixel)) * 1009ul +  \
      (unsigned long)sizeof(cr_scene)) * 1009ul + (unsigned long)sizeof(cr_err))

typedef struct cr_module_header {
    const char *version;  /* CURRAY_VERSION of the module's build */
    unsigned long layout; /* CR_MODULE_LAYOUT of the module's build */
} cr_module_header;

/* The entry of a module: exported, every other symbol of it hidden. */
#if defined(__GNUC__)
#define CR_MODULE_EXPORT __attribute__((visibility("default")))
#else
#define CR_MODULE_EXPORT
#endif

/* The table of module file (e.g. "curray_video.so"), whose entry function
 * is named entry, loaded on first use. what names the module in messages
 * ("video module"), needs the libraries it needs and how to get them. Returns
 * the table, or NULL with err set: the module not found (naming every place
 * looked in), not loadable (the loader's message, which names the missing
 * library), without its entry, or from another build. */
const void *cr_module_load(const char *file, const char *entry, const char *what,
                           const char *needs, cr_err *err);

#endif
