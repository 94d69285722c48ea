/* The CPU packet path (cpu_packet.h): compiled once per lane width, with
 * CR_LANES=4 for AVX2 and CR_LANES=8 for AVX-512F (src/render/CMakeLists.txt),
 * and -ffp-contract=off so that every lane rounds as the scalar code does.
 *
 * A packet is W lanes, each one ray: the Mino state, its step's stages, its
 * step sizes and its bookkeeping (accepted steps, rejected tries, turns,
 * disc crossings and polar turning points, the error monitor) in vectors
 * (lanes.h: the lane instance of mino_lane.h), and beside each lane the
 * scalar side of its ray (cr_ray with its constants and observer momentum,
 * the pixel being made). Each round makes one DP5 try in every lane and
 * decides, in vectors, what cr_trace_loop (trace.h) does for one ray:
 *   rejected: retry smaller next round (an error after CR_DP5_MAX_RETRIES);
 *   accepted: T by quadrature where the step left it unresolved
 *     (cr_ray_time_step's test); a step that may hold an event (it may
 *     cross the disc's plane, or the scene has spheres) goes through
 *     cr_trace_after_step on the lane's ray (its step copied out of the
 *     vectors); one that leaves the sky radius through cr_trace_move; any
 *     other moves to its end in the vectors, its crossing and turning point
 *     counted as cr_trace_count counts them; then the ends and the monitor of
 *     cr_trace_ends at the new state, in its order, from the lane-wise
 *     predicates of mino_lane.h.
 * Only the lanes with something scalar to do (an event, the sky cut, a
 * quadrature, an end) are visited one by one; an ended lane hands its pixel
 * over and takes the feed's next pixel at once (the feed runs on across
 * rows). A ray's start, its first ends (at 0 steps), every shading and every
 * event are the scalar core functions; the per-step formulas are
 * mino_lane.h's.
 */
#include "cpu_packet.h"

#include <float.h>
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
    cr_monitor mon; /* the monitor, out of the vectors at the ray's end */
    double x0[3];
    int i, j; /* the pixel; i < 0: the lane is idle */
} pk_lane;

typedef struct pk_packet {
    cr_mino_v c;
    cr_vd m[CR_MN], m1[CR_MN];
    cr_dp5_v st;
    cr_vd h, h_next, turns;
    cr_vd steps, tries;            /* accepted steps; rejected tries of this step */
    cr_vd mon_n, mon_mean, mon_m2; /* the error monitor (cr_monitor) */
    cr_vm n_cross, n_turn;         /* cr_ray.n_cross, n_turn */
    cr_vm live;                    /* lanes with a ray */
    pk_lane lane[PK_W];
} pk_packet;

/* Copy lane l's current step (start, end, stages, size h) into its ray. */
static void pk_scatter_step(pk_packet *p, int l, double h)
{
    cr_ray *r = &p->lane[l].ray;
    int k, s;
    for (k = 0; k < CR_MN; k++) {
        r->m[k] = p->m[k][l];
        r->m1[k] = p->m1[k][l];
        for (s = 0; s < 7; s++)
            r->st.k[s][k] = p->st.k[s][k][l];
    }
    r->hm = h;
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

/* Lane l's counts into its ray (for the scalar code), and back. */
static void pk_counts_out(pk_packet *p, int l)
{
    p->lane[l].ray.n_cross = (int)p->n_cross[l];
    p->lane[l].ray.n_turn = (int)p->n_turn[l];
}

static void pk_counts_in(pk_packet *p, int l)
{
    p->n_cross[l] = p->lane[l].ray.n_cross;
    p->n_turn[l] = p->lane[l].ray.n_turn;
}

/* cr_monitor_add in the lanes of mask on, for the monitor values e. */
static void pk_monitor_add(pk_packet *p, cr_vm on, cr_vd e)
{
    cr_vm use = on & (e >= 0.0) & (e <= DBL_MAX); /* e >= 0 and finite */
    cr_vd n = p->mon_n + 1.0;
    cr_vd d = e - p->mon_mean;
    cr_vd mean = p->mon_mean + d / n;
    cr_vd m2 = p->mon_m2 + d * (e - mean);
    p->mon_n = cr_v_sel(use, n, p->mon_n);
    p->mon_mean = cr_v_sel(use, mean, p->mon_mean);
    p->mon_m2 = cr_v_sel(use, m2, p->mon_m2);
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
        if (cr_trace_ends(f, r, &ln->px, &ln->mon, 0, 0.0)) {
            cr_trace_done(r, &ln->px, 0, &ln->mon);
            feed->done(feed->ctx, i, j, &ln->px);
            continue;
        }
        cr_v_mino_set(&p->c, l, &r->c);
        pk_gather_state(p, l);
        p->h[l] = p->h_next[l] = r->h_next;
        p->turns[l] = 0.0;
        p->steps[l] = p->tries[l] = 0.0;
        p->mon_n[l] = (double)ln->mon.n;
        p->mon_mean[l] = ln->mon.mean;
        p->mon_m2[l] = ln->mon.m2;
        pk_counts_in(p, l);
        p->live[l] = -1;
        ln->i = i;
        ln->j = j;
        return;
    }
    p->live[l] = 0;
    ln->i = -1;
}

/* Lane l's ray has ended (its pixel and its ray's counts are set): its cost
 * and monitor into the pixel, the pixel handed over, the next one taken. */
static void pk_finish(const cr_frame *f, pk_packet *p, int l, const cr_pixel_feed *feed)
{
    pk_lane *ln = &p->lane[l];
    ln->mon.n = (long)p->mon_n[l];
    ln->mon.mean = p->mon_mean[l];
    ln->mon.m2 = p->mon_m2[l];
    cr_trace_done(&ln->ray, &ln->px, (long)p->steps[l], &ln->mon);
    feed->done(feed->ctx, ln->i, ln->j, &ln->px);
    pk_load(f, p, l, feed);
}

void PK_FN(cr_packet_trace)(const cr_frame *f, const cr_pixel_feed *feed)
{
    pk_packet p;
    int l;
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
    while (cr_v_any(p.live)) {
        cr_vm retried, ok, cross, cut, n_cross, n_turn, acc, rej, fail, unres, quad, ev, moved;
        cr_vm check, hor, esc, lim;
        cr_vd err, turned, hstep;
        unsigned bits;
        retried = p.tries > 0.0;
        err = cr_dp5_try_v(&p.c, cr_ray_tolerance(f), p.h, p.m, &p.st, p.m1);
        ok = cr_dp5_control_v(err, retried, &p.h, &p.h_next);
        cr_mino_project_v(&p.c, ok, p.m1, &p.st);
        cross = cr_mino_may_cross_equator_v(p.m, p.m1);
        cut = cr_mino_cuts_sky_v(p.m, p.m1, f->w_sky);
        turned = p.turns + cr_mino_turns_v(p.m, p.m1);
        n_cross = cr_sign_change_v(cr_mino_disc_value_v(p.m), cr_mino_disc_value_v(p.m1));
        n_turn = cr_sign_change_v(cr_mino_polar_rate_v(p.m), cr_mino_polar_rate_v(p.m1));
        acc = p.live & ok;
        rej = p.live & ~ok;
        /* a rejected try: the retry next round, or the error (cr_ray_advance) */
        fail = rej & ((p.tries == (double)CR_DP5_MAX_RETRIES) | ((p.h > 0.0) == 0));
        p.tries = cr_v_sel(rej, p.tries + 1.0, cr_v_bc(0.0));
        p.steps = cr_v_sel(acc, p.steps + 1.0, p.steps);
        hstep = p.h; /* an accepted lane's step */
        /* the next try: an accepted step's successor, a rejected one's retry */
        p.h = cr_v_sel(ok, p.h_next, p.h);
        /* cr_ray_time_step's tests: T unresolved (t_quad), and its end's T
         * by quadrature where still needed (quad) */
        unres = acc & cr_mino_t_unresolved_v(&p.st, p.m, p.m1, hstep, cr_ray_tolerance(f));
        quad = unres & (((p.m1[CR_M_DW] < 0.0) & (p.m1[CR_M_W] < f->w_obj)) == 0);
        if (f->n_spheres > 0)
            ev = acc;
        else if (f->disc.enabled)
            ev = acc & cross;
        else
            ev = acc & 0;
        cut &= acc & ~ev;
        moved = acc & ~ev & ~cut;
        check = acc;
        /* the lanes with scalar work in this step, one by one */
        for (bits = cr_v_bits(quad | ev | cut); bits; bits &= bits - 1) {
            pk_lane *ln;
            double t;
            l = __builtin_ctz(bits);
            ln = &p.lane[l];
            pk_scatter_step(&p, l, hstep[l]);
            ln->ray.t_quad = unres[l] != 0;
            if (quad[l]) {
                cr_ray *r = &ln->ray;
                r->m1[CR_M_T] = cr_mino_t_quad(&r->c, &r->st, r->m, r->m1, r->hm, 1.0);
                p.m1[CR_M_T][l] = r->m1[CR_M_T];
            }
            if (!ev[l] && !cut[l])
                continue; /* moves in the vectors */
            t = p.turns[l];
            pk_counts_out(&p, l);
            if (ev[l]) {
                if (cr_trace_after_step(f, &ln->ray, &ln->px, ln->x0, &t)) {
                    check[l] = 0;
                    pk_finish(f, &p, l, feed);
                    continue;
                }
            } else {
                cr_trace_move(f, &ln->ray, &t);
            }
            pk_counts_in(&p, l);
            pk_gather_state(&p, l);
            p.turns[l] = t;
        }
        /* cr_trace_move in the vectors: the counts, the commit */
        p.n_cross -= moved & n_cross;
        p.n_turn -= moved & n_turn;
        {
            int k;
            for (k = 0; k < CR_MN; k++) {
                p.m[k] = cr_v_sel(moved, p.m1[k], p.m[k]);
                p.st.k[0][k] = cr_v_sel(moved, p.st.k[6][k], p.st.k[0][k]);
            }
            p.turns = cr_v_sel(moved, turned, p.turns);
        }
        /* cr_trace_ends at the new states, lane-wise */
        hor = check & cr_mino_at_horizon_v(p.m, f->w_stop);
        check &= ~hor;
        if (cr_v_any(check))
            pk_monitor_add(&p, check, cr_mino_monitor_v(&p.c, p.m));
        esc = check & cr_mino_escaping_v(p.m, f->w_sky);
        lim = check & ~esc &
              ((p.steps >= (double)f->max_steps) | (p.turns >= f->max_turns));
        for (bits = cr_v_bits(fail | hor | esc | lim); bits; bits &= bits - 1) {
            pk_lane *ln;
            l = __builtin_ctz(bits);
            ln = &p.lane[l];
            pk_counts_out(&p, l);
            if (fail[l]) {
                ln->px.outcome = CR_OUT_ERROR;
            } else if (hor[l]) {
                cr_trace_horizon(f, &ln->px);
            } else if (esc[l]) {
                int k;
                for (k = 0; k < CR_MN; k++)
                    ln->ray.m[k] = p.m[k][l];
                cr_sky_shade(f, &ln->ray, &ln->px);
            } else {
                cr_trace_limit(f, &ln->px);
            }
            pk_finish(f, &p, l, feed);
        }
    }
}
