/* curray base: will this much memory fit?
 *
 * The limit is the physical memory, or the address-space or data limit
 * (ulimit -v, -d) when lower. Used to refuse a run, a frame buffer or a
 * decoded image before it is allocated, rather than being killed by the
 * out-of-memory killer or failing half-way. */
#ifndef CR_BASE_MEMCHECK_H
#define CR_BASE_MEMCHECK_H

#include "error.h"

/* 0 when bytes fit; else -1 with err "needs about X GiB of memory, more
 * than the Y GiB of <which limit>" (the caller says what needs it). */
int cr_mem_check(double bytes, cr_err *err);

/* The default stack of a new thread, bytes (what each thread reserves of
 * the address space). */
double cr_mem_thread_stack(void);

#endif
