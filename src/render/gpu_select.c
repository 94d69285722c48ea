/* curray cuda backend: which devices to render on (gpu.h, cr_gpu_select,
 * cr_gpu_choose). Plain C without CUDA calls of its own (cr_gpu_choose asks
 * cr_gpu_devices), built into every build (with and without
 * CUDA) so that the selection is the same, and unit-tested with made-up
 * device tables (tests/test_gpu_select.c). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "gpu.h"
#include "../base/limits.h" /* CR_MAX_GPUS */

/* Append printf-style text to msg (size n), cut at the end. */
static void cr_gpu_append(char *msg, size_t n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static void cr_gpu_append(char *msg, size_t n, const char *fmt, ...)
{
    size_t len = strlen(msg);
    va_list ap;
    if (len + 1 >= n)
        return;
    va_start(ap, fmt);
    vsnprintf(msg + len, n - len, fmt, ap);
    va_end(ap);
}

int cr_gpu_select(const cr_gpu_device *table, int n_devices, const int *enabled, int n_enabled,
                  int *chosen, int max_chosen, cr_err *err)
{
    char skipped[CR_ERR_MSG] = "", idle[CR_ERR_MSG] = "";
    int d, n_chosen = 0, n_on = 0;

    if (n_devices < 0)
        n_devices = 0;
    for (d = 0; d < n_devices; d++) {
        int on = enabled && d < n_enabled && enabled[d];
        n_on += on;
        if (on && table[d].usable) {
            if (n_chosen < max_chosen)
                chosen[n_chosen++] = d;
        } else if (on) {
            cr_gpu_append(skipped, sizeof skipped, "%sGPU %d is unusable (%s)",
                          skipped[0] ? "; " : "", d,
                          table[d].why[0] ? table[d].why : "no reason given");
        } else if (table[d].usable) {
            cr_gpu_append(idle, sizeof idle, "%s%d", idle[0] ? ", " : "", d);
        }
    }
    if (n_chosen > 0) {
        if (err)
            snprintf(err->msg, sizeof err->msg, "%s", skipped);
        return n_chosen;
    }
    if (n_devices == 0)
        cr_err_set(err, "no CUDA device found");
    else if (n_on == 0 && idle[0])
        cr_err_set(err,
                   "no GPU is enabled in the configuration; usable: %s (enable one with "
                   "gpus: {<number>: {enabled: true}})",
                   idle);
    else if (n_on == 0)
        cr_err_set(err, "no GPU is enabled in the configuration, and none is usable");
    else if (idle[0])
        cr_err_set(err, "%s; usable but not enabled in the configuration: %s", skipped, idle);
    else
        cr_err_set(err, "%s", skipped);
    return 0;
}

int cr_gpu_choose(const int *enabled, int n_enabled, int *chosen, int max_chosen, cr_err *err)
{
    cr_gpu_device table[CR_MAX_GPUS];
    int n = cr_gpu_devices(table, CR_MAX_GPUS, err);
    if (n > CR_MAX_GPUS)
        n = CR_MAX_GPUS; /* gpus: numbers only go this far */
    return n > 0 ? cr_gpu_select(table, n, enabled, n_enabled, chosen, max_chosen, err) : 0;
}

int cr_gpu_for_local_rank(const int *chosen, int n_chosen, int local_rank, int local_size,
                          cr_err *note)
{
    if (note)
        note->msg[0] = '\0';
    if (!chosen || n_chosen < 1 || local_rank < 0)
        return -1;
    if (note && local_size > n_chosen)
        snprintf(note->msg, sizeof note->msg,
                 "%d MPI ranks on this node share its %d usable GPU%s (local rank k uses the "
                 "k-th modulo %d)",
                 local_size, n_chosen, n_chosen > 1 ? "s" : "", n_chosen);
    else if (note && local_size > 0 && local_size < n_chosen)
        snprintf(note->msg, sizeof note->msg,
                 "%d usable GPU%s on this node but %d MPI rank%s: %d GPU%s stay%s idle (one GPU "
                 "per rank; start a rank per GPU)",
                 n_chosen, n_chosen > 1 ? "s" : "", local_size, local_size > 1 ? "s" : "",
                 n_chosen - local_size, n_chosen - local_size > 1 ? "s" : "",
                 n_chosen - local_size > 1 ? "" : "s");
    return chosen[local_rank % n_chosen];
}
