/* curray cpu backend: the packet path, W rays at a time in vector lanes
 * (cpu_packet.c), and the pixel feed the worker threads give it. */
#ifndef CR_RENDER_CPU_PACKET_H
#define CR_RENDER_CPU_PACKET_H

#include "../core/defs.h"

/* Where a tracer takes its pixels from and gives them back: next() sets the
 * next pixel (i, j) of the frame to trace and returns 1, or returns 0 when
 * there is none left (or the render is cancelled); done() receives each
 * pixel traced, in any order. */
typedef struct cr_pixel_feed {
    int (*next)(void *ctx, int *i, int *j);
    void (*done)(void *ctx, int i, int j, const cr_pixel *px);
    void *ctx;
} cr_pixel_feed;

/* Trace the feed's pixels of the prepared frame f until it runs dry: every
 * pixel as cr_trace_pixel traces it (trace.h), bit for bit, W rays at a
 * time: each lane is one ray under the Mino integrator with its own step
 * size, accept/reject and ends; a lane whose ray ends takes the feed's next
 * pixel. Events (hits, the cut at the sky radius) and the start and end of
 * each ray run the scalar core code on that lane's ray. Frames with
 * antialiasing (samples > 1), rays under rk4 and rays from an observer
 * inside the horizon (ray.h's ingoing chart) are traced by the scalar code
 * within the same call. _x4 needs AVX2, _x8 AVX-512F: call only where
 * the CPU has them (cpu.c's dispatch); either is absent (NULL-free: not
 * declared as built) unless CR_HAVE_PACKETS. */
void cr_packet_trace_x4(const cr_frame *f, const cr_pixel_feed *feed);
void cr_packet_trace_x8(const cr_frame *f, const cr_pixel_feed *feed);

#endif
