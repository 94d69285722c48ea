/* The CPU packet path (cpu_packet.h): compiled once per lane width, with
 * CR_LANES=4 for AVX2 and CR_LANES=8 for AVX-512F (src/render/CMakeLists.txt),
 * and -ffp-contract=off so that every lane rounds as the scalar code does.
 *
 * A packet is W lanes, each one ray: the Mino state, its step's stages and
 * step sizes in vectors (lanes.h: the lane instance of mino_lane.h), and
 * beside each lane the scalar side of its ray (cr_ray with its constants
 * and observer momentum, the pixel being made, the error monitor, the step
 * and retry counts). Each round makes one DP5 try in every lane; then lane
 * by lane, as cr_trace_loop (trace.h) does for one ray:
 *   rejected: retry smaller next round (an error after CR_DP5_MAX_RETRIES);
 *   accepted: a step that may hold an event (it may cross the disc's plane,
 *     or the scene has spheres) goes through cr_trace_after_step on the
 *     lane's ray (its step copied out of the vectors); one that leaves the
 *     sky radius through cr_trace_move; any other moves to its end in the
 *     vectors (its crossing and turning point counted as cr_trace_count
 *     counts them, from the lane-wise event values); then the ends and the monitor of cr_trace_ends at the new
 *     state, in its order, from the lane-wise predicates of mino_lane.h
 *     (shading on the lane's ray).
 * A ray's start, its first ends (at 0 steps), every shading and every event
 * are the scalar core functions; the per-step formulas are mino_lane.h's.
 */
#include "cpu_packet.h"

#include <string.h>

#include "../core/lanes.h"
#include "../core/trace.h"

#ifndef CR_LANES
#error "cpu_packet.c is compiled with CR_LANES=4 or 8"
#endif

#define PK_W CR_LANES
#define PK_CAT2(a, b) a##_x##b
#define PK_CAT(a, b) PK_CAT2(a, b)
#define PK_FN(a) PK_CAT(a, CR_LANES)

/* The scalar side of one lane. */
typedef struct pk_lane {
    cr_ray ray; /* constants, observer momentum; the step copied out at events */
    cr_pixel px;
    cr_monitor mon;
    double x0[3];
    long steps;
    int tries; /* rejected tries of the current step */
    int i, j;  /* the pixel; i < 0: the lane is idle */
} pk_lane;

typedef struct pk_packet {
    cr_mino_v c;
    cr_vd m[CR_MN], m1[CR_MN];
    cr_dp5_v st;
    cr_vd h, h_next, turns;
    pk_lane lane[PK_W];
} pk_packet;

/* Copy lane l's current step (start, end, stages, size) into its ray. */
static void pk_scatter_step(pk_packet *p, int l)
{
    cr_ray *r = &p->lane[l].ray;
    int k, s;
    for (k = 0; k < CR_MN; k++) {
        r->m[k] = p->m[k][l];
        r->m1[k] = p->m1[k][l];
        for (s = 0; s < 7; s++)
            r->st.k[s][k] = p->st.k[s][k][l];
    }
    r->hm = p->h[l];
}

/* cr_ray_time_step (ray.h) for lane l's accepted step: the same test on
 * the lane's values (cr_mino_t_unresolved's estimate, term for term), and
 * only where it holds the step copied out for the quadrature. */
static void pk_time_step(const cr_frame *f, pk_packet *p, int l)
{
    cr_ray *r = &p->lane[l].ray;
    cr_dp5 st;
    double y0[CR_MN], y1[CR_MN];
    int k, s;
    r->t_quad = 0;
    if (p->m1[CR_M_DW][l] < 0.0 && p->m1[CR_M_W][l] < f->w_obj)
        return;
    for (s = 0; s < 7; s++)
        st.k[s][CR_M_T] = p->st.k[s][CR_M_T][l];
    y0[CR_M_T] = p->m[CR_M_T][l];
    y1[CR_M_T] = p->m1[CR_M_T][l];
    if (!cr_mino_t_unresolved(&st, y0, y1, p->h[l], f->tolerance))
        return;
    for (k = 0; k < CR_MN; k++) {
        r->m[k] = p->m[k][l];
        r->m1[k] = p->m1[k][l];
        for (s = 0; s < 7; s++)
            r->st.k[s][k] = p->st.k[s][k][l];
    }
    r->hm = p->h[l];
    r->t_quad = 1;
    r->m1[CR_M_T] = cr_mino_t_quad(&r->c, &r->st, r->m, r->m1, r->hm, 1.0);
    p->m1[CR_M_T][l] = r->m1[CR_M_T];
}

/* Lane l's state (and the first stage there) from its ray. */
static void pk_gather_state(pk_packet *p, int l)
{
    const cr_ray *r = &p->lane[l].ray;
    int k;
    for (k = 0; k < CR_MN; k++) {
        p->m[k][l] = r->m[k];
        p->st.k[0][k][l] = r->st.k[0][k];
    }
}

/* Start lanes l's next ray: the feed's pixels in turn, each traced at once
 * when it needs no steps of the packet (outside the picture, rk4, ends
 * before its first step), until one is left for the lane or the feed runs
 * dry (the lane is then idle). */
static void pk_load(const cr_frame *f, pk_packet *p, int l, const cr_pixel_feed *feed)
{
    pk_lane *ln = &p->lane[l];
    int i, j;
    while (feed->next(feed->ctx, &i, &j)) {
        cr_ray *r = &ln->ray;
        if (!cr_trace_point_ray(f, (double)i, (double)j, r, &ln->px)) {
            feed->done(feed->ctx, i, j, &ln->px);
            continue;
        }
        if (r->kind != CR_INTEG_MINO || cr_ray_ingoing(r)) {
            /* rk4, and rays from inside the horizon (their chart changes) */
            ln->px = cr_trace_loop(f, r);
            feed->done(feed->ctx, i, j, &ln->px);
            continue;
        }
        cr_trace_start(f, r, &ln->px, ln->x0);
        ln->mon.n = 0;
        ln->mon.mean = ln->mon.m2 = 0.0;
        ln->steps = 0;
        ln->tries = 0;
        if (cr_trace_ends(f, r, &ln->px, &ln->mon, 0, 0.0)) {
            cr_trace_done(r, &ln->px, 0, &ln->mon);
            feed->done(feed->ctx, i, j, &ln->px);
            continue;
        }
        cr_v_mino_set(&p->c, l, &r->c);
        pk_gather_state(p, l);
        p->h[l] = p->h_next[l] = r->h_next;
        p->turns[l] = 0.0;
        ln->i = i;
        ln->j = j;
        return;
    }
    ln->i = -1;
}

/* Lane l's ray has ended (its pixel is set): hand the pixel over, take the
 * next. */
static void pk_finish(const cr_frame *f, pk_packet *p, int l, const cr_pixel_feed *feed)
{
    pk_lane *ln = &p->lane[l];
    cr_trace_done(&ln->ray, &ln->px, ln->steps, &ln->mon);
    feed->done(feed->ctx, ln->i, ln->j, &ln->px);
    pk_load(f, p, l, feed);
}

void PK_FN(cr_packet_trace)(const cr_frame *f, const cr_pixel_feed *feed)
{
    pk_packet p;
    int l, live;
    if (f->samples >= 2 && f->samples <= CR_MAX_SAMPLES) {
        /* antialiasing: the scalar tracer, pixel by pixel */
        int i, j;
        while (feed->next(feed->ctx, &i, &j)) {
            cr_pixel px = cr_trace_pixel(f, i, j);
            feed->done(feed->ctx, i, j, &px);
        }
        return;
    }
    memset(&p, 0, sizeof p);
    for (l = 0; l < PK_W; l++)
        pk_load(f, &p, l, feed);
    for (;;) {
        cr_vm retried, ok, cross, cut, hor, esc, n_cross, n_turn;
        cr_vm moved; /* lanes whose step ends in the vectors */
        cr_vm check; /* lanes whose new state is checked for the ends */
        cr_vd err, turned, mon;
        live = 0;
        for (l = 0; l < PK_W; l++) {
            live |= p.lane[l].i >= 0;
            retried[l] = p.lane[l].tries > 0 ? -1 : 0;
        }
        if (!live)
            break;
        err = cr_dp5_try_v(&p.c, f->tolerance, p.h, p.m, &p.st, p.m1);
        ok = cr_dp5_control_v(err, retried, &p.h, &p.h_next);
        cross = cr_mino_may_cross_equator_v(p.m, p.m1);
        cut = cr_mino_cuts_sky_v(p.m, p.m1, f->w_sky);
        turned = p.turns + cr_mino_turns_v(p.m, p.m1);
        n_cross = cr_sign_change_v(cr_mino_disc_value_v(p.m), cr_mino_disc_value_v(p.m1));
        n_turn = cr_sign_change_v(cr_mino_polar_rate_v(p.m), cr_mino_polar_rate_v(p.m1));
        moved = ok & 0;
        check = moved;
        for (l = 0; l < PK_W; l++) {
            pk_lane *ln = &p.lane[l];
            if (ln->i < 0)
                continue;
            if (!ok[l]) {
                if (ln->tries == CR_DP5_MAX_RETRIES || !(p.h[l] > 0.0)) {
                    ln->px.outcome = CR_OUT_ERROR;
                    pk_finish(f, &p, l, feed);
                } else {
                    ln->tries++;
                }
                continue;
            }
            ln->tries = 0;
            ln->steps++;
            pk_time_step(f, &p, l);
            if (f->n_spheres > 0 || (f->disc.enabled && cross[l])) {
                double t = p.turns[l];
                pk_scatter_step(&p, l);
                if (cr_trace_after_step(f, &ln->ray, &ln->px, ln->x0, &t)) {
                    pk_finish(f, &p, l, feed);
                    continue;
                }
                pk_gather_state(&p, l);
                p.turns[l] = t;
            } else if (cut[l]) {
                double t = p.turns[l];
                pk_scatter_step(&p, l);
                cr_trace_move(f, &ln->ray, &t);
                pk_gather_state(&p, l);
                p.turns[l] = t;
            } else {
                /* cr_trace_move in the vectors: the counts here, the commit below */
                ln->ray.n_cross += n_cross[l] != 0;
                ln->ray.n_turn += n_turn[l] != 0;
                moved[l] = -1;
            }
            check[l] = -1;
        }
        /* the next try: an accepted step's successor (a lane started this
         * round has h = h_next already), a rejected one's retry */
        p.h = cr_v_sel(ok, p.h_next, p.h);
        {
            int k;
            for (k = 0; k < CR_MN; k++) {
                p.m[k] = cr_v_sel(moved, p.m1[k], p.m[k]);
                p.st.k[0][k] = cr_v_sel(moved, p.st.k[6][k], p.st.k[0][k]);
            }
            p.turns = cr_v_sel(moved, turned, p.turns);
        }
        if (!cr_v_any(check))
            continue;
        /* cr_trace_ends at the new states, lane-wise */
        hor = cr_mino_at_horizon_v(p.m, f->w_stop);
        esc = cr_mino_escaping_v(p.m, f->w_sky);
        mon = cr_mino_monitor_v(&p.c, p.m);
        for (l = 0; l < PK_W; l++) {
            pk_lane *ln = &p.lane[l];
            if (!check[l])
                continue;
            if (hor[l]) {
                cr_trace_horizon(f, &ln->px);
                pk_finish(f, &p, l, feed);
                continue;
            }
            cr_monitor_add(&ln->mon, mon[l]);
            if (esc[l]) {
                int k;
                for (k = 0; k < CR_MN; k++)
                    ln->ray.m[k] = p.m[k][l];
                cr_sky_shade(f, &ln->ray, &ln->px);
                pk_finish(f, &p, l, feed);
            } else if (ln->steps >= f->max_steps || p.turns[l] >= f->max_turns) {
                cr_trace_limit(f, &ln->px);
                pk_finish(f, &p, l, feed);
            }
        }
    }
}
