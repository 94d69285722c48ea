/* Stand-ins for curray's output modules (module.h), for test_modules.sh:
 *   FAKE_OTHER_BUILD  a curray_video.so whose header is another build's
 *                     (version "0.0.0-other"): curray must refuse it
 *   FAKE_NEEDS_GONE   a curray_fits.so that needs libcr_gone.so, a library
 *                     the loader cannot find: curray must name it */
#include "output/module.h"

#if defined(FAKE_OTHER_BUILD)
typedef struct {
    cr_module_header head;
    void *fn;
} fake_table;
CR_MODULE_EXPORT const fake_table *curray_video_module(void);
CR_MODULE_EXPORT const fake_table *curray_video_module(void)
{
    static const fake_table t = {{"0.0.0-other", CR_MODULE_LAYOUT}, 0};
    return &t;
}
#elif defined(FAKE_NEEDS_GONE)
int cr_gone(void);
CR_MODULE_EXPORT int curray_fits_module(void);
CR_MODULE_EXPORT int curray_fits_module(void)
{
    return cr_gone();
}
#else
/* libcr_gone.so itself */
int cr_gone(void);
int cr_gone(void)
{
    return 0;
}
#endif
