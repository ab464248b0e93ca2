"""The C of KD tracking between a performer's samples, for ``pk_poll``'s tick
(``kernel_poll``; the Python it mirrors operation for operation:
``interface/track_poll.py`` and the tracking controllers): the walk in place, the
ground under a point, a blend's fraction, a get-up's and a motion library's view and
a reaction's weight. Kept apart from the loop because it is one idea, the tracker's,
and so that each file stays readable; it reads ``pk_poll_plan`` (``POLL_TYPES``).
"""

TRACK_SOURCE = r"""
/* A performer's sample among a run's events (its kind; -1: Python's) */
#define PK_EV_SAMPLE -2

/* runtime._on_channels, then flush, of a sample at s for an angles tracker
   (poll_track): its channels' values stored (those it has), Tracker.sampled's
   last_sample and phase (a sample that comes between two control steps moves them to
   itself: the tick at s is the tracker's); 1: a value is Python's (nothing done) */
static int pk_sample(pk_poll_plan *p, int e, int s)
{
    const double *v = p->ch_v + (long long)e * p->ch_n;
    const char *h = p->ch_has + (long long)e * p->ch_n;
    for (int i = 0; i < p->ch_n; i++)
        if (h[i] == 2)
            return 1;
    double *vals = p->walk ? p->walk->raw : p->t_vals;  /* (walking: the raw values) */
    char *has = p->walk ? p->walk->raw_has : p->t_has;
    for (int i = 0; i < p->ch_t; i++) {
        if (h[i]) {
            vals[i] = v[i];
            if (has)
                has[i] = 1;
        }
    }
    for (int i = p->ch_t; i < p->ch_n; i++)  /* (a contact's hand: pk_contact_rates) */
        if (h[i])
            p->c_xy[i - p->ch_t] = v[i];
    if (p->t_cl_sample && h[p->ch_t]) {  /* (a KD tracker's clearance: pk_fresh's) */
        p->t_cl[1] = v[p->ch_t];
        p->t_cl_has[1] = 1;
    }
    p->t_sample = s;
    p->t_fresh = 1;
    if (s - p->t_phase >= p->t_every || s < p->t_phase)
        p->t_phase = s;
    return 0;
}

static double pk_ground(const double *spans, int n, double x, int *found);

/* A KD tracker's first tick after a sample the run applied (TrackPoll.ready at a
   sample's tick, resumed): velocity_sample (the performed velocities differenced from
   the sample before, or none to difference) and _lift (the ground under the root's
   place, the clearance or -PRESS), for pk_track_pose at this tick */
static void pk_fresh(pk_poll_plan *p)
{
    int vel = 0;
    double h = 0.0;
    if (!p->track->has_prev || p->t_sample != p->t_prev) {
        if (p->track->has_prev && p->t_sample > p->t_prev) {
            vel = 1;
            h = (double)(p->t_sample - p->t_prev) * p->t_dt;
        } else {
            vel = 2;
        }
        p->t_prev = p->t_sample;
    }
    p->t_pose = 1;
    p->t_vel = vel;
    p->t_h = h;
    if (p->walk) {  /* (TrackPoll._walk_from's: the view's lift is pk_walk_view's) */
        p->walk->extra = p->c_xy[0] > 0.0 ? p->c_xy[0] : -0.003;  /* -PRESS */
        return;
    }
    int lift = 0;
    double ground = 0.0, extra = 0.0;
    if (p->t_soles) {
        double g = pk_ground(p->spans, p->n_spans, p->t_x0 + p->t_vals[0], &lift);
        if (lift) {
            ground = g;
            extra = p->c_xy[0] > 0.0 ? p->c_xy[0] : -0.003;  /* -PRESS */
        }
    }
    p->t_lift = lift;
    p->t_ground = ground;
    p->t_extra = extra;
}

/* GaitCycle._raw_one(u, xi) less start: GaitCycle.travel at u */
static double pk_cycle_x(const pk_walk *w, double u)
{
    long long k = (long long)u;
    if (k > w->n_frames - 2)
        k = w->n_frames - 2;
    double v = w->frames[k * w->width + w->xi], q = w->frames[(k + 1) * w->width + w->xi];
    return v + (q - v) * (u - (double)k);
}

static double pk_py_mod1(double x)  /* Python's x % 1.0 */
{
    double m = fmod(x, 1.0);
    if (m != 0.0) {
        if (m < 0.0)
            m += 1.0;
    } else {
        m = 0.0;
    }
    return m;
}

/* Simulation.ground_surface at x: the highest of the spans over x (lo, hi, x0, y0,
   x1, y1, half each), *found 0 when none is */
static double pk_ground(const double *spans, int n, double x, int *found)
{
    double best = 0.0;
    *found = 0;
    for (int k = 0; k < n; k++) {
        const double *g = spans + 7 * k;
        if (g[0] <= x && x <= g[1]) {
            double y = g[3] + (g[5] - g[3]) * (x - g[2]) / (g[4] - g[2]) + g[6];
            if (!*found || y > best)
                best = y;
            *found = 1;
        }
    }
    return best;
}

/* Tracker._fraction: how far a blend begun at ``at`` has come at s (0..1) */
static double pk_fraction(int s, int at, int steps)
{
    if (steps <= 0)
        return 1.0;
    double w = (double)(s - at) / (double)steps;
    return w >= 1.0 ? 1.0 : w > 0.0 ? w : 0.0;
}

/* kd_pull.mix(came, b, w) in the values' order (b: the view's values, a value b lacks
   is not in the view), into view; the clearance's too (cl: came's, b's; has) */
static void pk_mix(pk_poll_plan *p, double w, double *clearance)
{
    int n = p->t_n;
    if (w >= 1.0) {
        for (int i = 0; i < n; i++) {
            p->t_view[i] = p->t_vals[i];
            p->t_view_has[i] = p->t_has ? p->t_has[i] : 1;
        }
        *clearance = p->t_cl_has[1] ? p->t_cl[1] : 0.0;
        return;
    }
    for (int i = 0; i < n; i++) {
        if (p->t_has && !p->t_has[i]) {
            p->t_view[i] = 0.0;
            p->t_view_has[i] = 0;
            continue;
        }
        double v = p->t_vals[i];
        double u = (p->t_came_has == 0 || p->t_came_has[i]) ? p->t_came[i] : v;
        p->t_view[i] = u + (v - u) * w;
        p->t_view_has[i] = 1;
    }
    if (p->t_cl_has[1]) {
        double v = p->t_cl[1], u = p->t_cl_has[0] ? p->t_cl[0] : v;
        *clearance = u + (v - u) * w;
    } else {
        *clearance = 0.0;
    }
}

/* GetUp.view(s) in the values' order into the view (a value the pose lacks is not in
   it), its clearance; supported(): a foot or a hand touching (no_lift: none does) */
static void pk_getup(pk_poll_plan *p, int s, double *clearance, int *no_lift)
{
    int n = p->t_n, i = p->g_n - 1;
    for (int k = 0; k < p->g_n; k++) {
        if (s < p->g_ends[k]) {
            i = k;
            break;
        }
    }
    int start = i == 0 ? p->g_at : p->g_ends[i - 1];
    int den = p->g_ends[i] - start;
    double x = (double)(s - start) / (double)(den > 1 ? den : 1);
    double m = x > 0.0 ? x : 0.0;  /* min(1.0, max(0.0, x)) */
    double w = m < 1.0 ? m : 1.0;
    const double *a = p->g_vals + i * n, *b = a + n;
    const char *ah = p->g_has + i * n, *bh = ah + n;
    for (int j = 0; j < n; j++) {
        if (!bh[j]) {
            p->t_view[j] = 0.0;
            p->t_view_has[j] = 0;
            continue;
        }
        double v = b[j], u = ah[j] ? a[j] : v;
        p->t_view[j] = u + (v - u) * w;
        p->t_view_has[j] = 1;
    }
    if (p->g_cl_has[i + 1]) {
        double v = p->g_cl[i + 1], u = p->g_cl_has[i] ? p->g_cl[i] : v;
        *clearance = u + (v - u) * w;
    } else {
        *clearance = 0.0;
    }
    int touching = 0;
    for (int k = 0; k < p->g_n_feel && !touching; k++)
        each_arbiter(p->g_feel[k], pk_touched, &touching);
    *no_lift = !touching;
}

/* LibraryReactions._library_view at s (MotionLibrary.channels_at, root.x placed by
   the offset, blended in from the performer's values over l_blend) into the view, its
   clearance; the pulls' weight (_library_weight) */
static double pk_library(pk_poll_plan *p, int s, double *clearance)
{
    int n = p->t_n;
    double t = (double)(s - p->l_start) * p->rx_dt;
    double u = 0.0 > t ? 0.0 : t;  /* min(max(t, 0.0), duration) * rate */
    u = p->l_duration < u ? p->l_duration : u;
    u = u * p->l_rate;
    long long k = 0;
    if (p->l_span > 1) {
        k = (long long)u;
        if (k > p->l_span - 2)
            k = p->l_span - 2;
    }
    double f = u - (double)k;
    long long kb = p->l_first + k + 1;
    if (kb > p->l_len - 1)
        kb = p->l_len - 1;
    const double *a = p->l_frames + (p->l_first + k) * p->l_width;
    const double *b = p->l_frames + kb * p->l_width;
    int blending = p->l_blend > 0.0 && t < p->l_blend;
    double w = blending ? t / p->l_blend : 1.0;
    for (int i = 0; i < n; i++) {
        int j = p->l_col[i];
        int perf = p->t_has == 0 || p->t_has[i];
        if (j < 0) {  /* the performer's, blending in; else not in the view */
            p->t_view[i] = blending && perf ? p->t_vals[i] : 0.0;
            p->t_view_has[i] = blending && perf;
            continue;
        }
        double v = a[j] + (b[j] - a[j]) * f;
        if (i == 0)
            v += p->l_offset;  /* (root.x, the values' first) */
        if (blending) {
            double c = perf ? p->t_vals[i] : v;
            v = c + (v - c) * w;
        }
        p->t_view[i] = v;
        p->t_view_has[i] = 1;
    }
    *clearance = 0.0;
    if (p->l_cl >= 0) {
        double v = a[p->l_cl] + (b[p->l_cl] - a[p->l_cl]) * f;
        if (blending) {
            double c = p->t_cl_has[1] ? p->t_cl[1] : v;
            v = c + (v - c) * w;
        }
        *clearance = v;
    } else if (blending && p->t_cl_has[1]) {
        *clearance = p->t_cl[1];
    }
    double lw = (p->l_blend <= 0.0 || t >= p->l_blend) ? 1.0 : t / p->l_blend;
    return p->l_low + (p->l_weight - p->l_low) * lw;
}

/* Tracker._weight of a reaction under way (not a fall's get-up: Python's), at s */
static double pk_react_weight(pk_poll_plan *p, int s)
{
    double t = (double)(s - p->rx_start) * p->rx_dt;
    if (t < p->rx_hold)
        return p->rx_weight;
    t -= p->rx_hold;
    if (t >= p->rx_recover) {
        if (p->rx_done < 0)
            p->rx_done = s;  /* (Python: the reaction and the step end here) */
        return 1.0;
    }
    return p->rx_weight + (1.0 - p->rx_weight) * t / p->rx_recover;
}

/* WalkInPlace._walk_advance at s between samples (the same channels: no new step) */
static void pk_walk_advance(pk_walk *w, int s)
{
    double h = (w->has_at && s > w->at) ? (double)(s - w->at) * w->dt : 0.0;
    if (w->walking && w->has_last_at && (double)(s - w->last_at) * w->dt > w->stop_after)
        w->walking = 0;
    if (w->blend > 0.0) {
        double v;
        if (w->walking) {
            v = w->weight + h / w->blend;
            w->weight = v < 1.0 ? v : 1.0;  /* min(1.0, v) */
        } else {
            v = w->weight - h / w->blend;
            w->weight = v > 0.0 ? v : 0.0;  /* max(0.0, v) */
        }
    } else {
        w->weight = w->walking ? 1.0 : 0.0;
    }
    if (w->weight > 0.0 && h > 0.0) {
        double nw = w->phase + w->speed * h;
        double m = pk_py_mod1(nw);
        double span = w->b - w->a;
        double gone = ((pk_cycle_x(w, w->a + span * m) - w->start)
                       - (pk_cycle_x(w, w->a + span * w->phase) - w->start))
                      + w->stride * (double)(long long)nw;
        w->travel = w->travel + w->weight * gone;
        w->phase = m;
    }
    w->at = s;
    w->has_at = 1;
}

/* WalkInPlace._walk_advance at a sample's tick: the performed pose's feet
   (_feet_gap: the chain posed from the root, turned by root.angle); a foot lift past
   the other's, the other foot's last, is a step (the rhythm's period, the cycle's
   speed toward the other foot's lift); then the advance (pk_walk_advance) */
static void pk_walk_step(pk_walk *w, int s)
{
    if (w->feet && (w->raw_has == 0 || w->raw_has[w->f_angle])) {
        double angle = w->raw[w->f_angle] * DEG;
        pk_pose(w->feet, w->raw, w->raw_has, w->f_root, 0.0, 0.0, angle, cos(angle),
                sin(angle), w->poses);
        const double *a = w->poses + 5 * w->f_link[0], *b = w->poses + 5 * w->f_link[1];
        double gap = (a[1] + a[4] * w->f_gx[0] + a[3] * w->f_gy[0])
                     - (b[1] + b[4] * w->f_gx[1] + b[3] * w->f_gy[1]);
        int side = gap > w->f_lift ? 0 : gap < -w->f_lift ? 1 : -1;
        if (side >= 0 && side != w->last_side) {
            if (w->has_last_at) {
                double d = (double)(s - w->last_at) * w->dt;
                if (w->f_lo <= d && d <= w->f_hi && w->last_side >= 0) {
                    double target = w->f_lifts[side];
                    w->period = d;
                    w->has_period = 1;
                    if (!w->walking) {
                        w->walking = 1;
                        w->phase = target;
                        w->speed = 0.5 / d;
                    } else {  /* min(1.0, max(0.25, 0.5 + e)) / period */
                        double e = pk_py_mod1(target - w->phase + 0.5) - 0.5;
                        double u = 0.5 + e;
                        u = u > 0.25 ? u : 0.25;
                        u = u < 1.0 ? u : 1.0;
                        w->speed = u / d;
                    }
                }
            }
            w->last_side = side;
            w->last_at = s;
            w->has_last_at = 1;
        }
    }
    pk_walk_advance(w, s);
}

/* WalkInPlace._walked's view of the performer's values: the cycle's joints blended in
   (GaitCycle.blend_into), root.x on by the travel; the lift's ground under it
   (Simulation.ground_surface): *ground, *found (0: none under it) */
static void pk_walk_view(pk_walk *w, double x0, double *ground, int *found)
{
    int n = w->n_vals;
    for (int i = 0; i < n; i++) {
        w->view[i] = w->raw[i];
        w->view_has[i] = w->raw_has ? w->raw_has[i] : 1;
    }
    if (!(w->weight <= 0.0 && w->travel == 0.0)) {
        if (w->weight > 0.0) {
            double u = w->a + (w->b - w->a) * w->phase;
            long long k = (long long)u;
            if (k > w->n_frames - 2)
                k = w->n_frames - 2;
            double f = u - (double)k;
            const double *p = w->frames + k * w->width, *q = p + w->width;
            for (int r = 0; r < w->n_rows; r++) {
                int i = w->row_ch[r], j = w->row_val[r];
                double v = p[i];
                double wv = v + (q[i] - v) * f - w->drift[i] * w->phase;
                double c = (w->raw_has == 0 || w->raw_has[j]) ? w->raw[j] : wv;
                w->view[j] = c + (wv - c) * w->weight;
                w->view_has[j] = 1;
            }
        }
        if (w->view_has[0])  /* root.x, the values' first */
            w->view[0] = w->view[0] + w->travel;
    }
    *found = 0;
    *ground = 0.0;
    if (w->lift)
        *ground = pk_ground(w->spans, w->n_spans, x0 + w->view[0], found);
}

"""
