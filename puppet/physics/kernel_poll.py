"""The compiled kernel's stepping loop (``pk_poll``): Chipmunk's step, and between the
steps what a state that polls at the control rate does in Python, for as long as
nothing else is due.

A state machine polling every step (a state's ``control_rate: 480``) costs a Luxo
step, 2.3 us of physics, another 1.5-2 us of Python: a tick, the poll (a contact read,
an angle) and a blend's eased target. ``pk_poll`` steps the space from ``now`` and,
after each step, does the work ``Session.advance`` would do there, in its order:

  * at a frame's end (``frame_every``), the session's check that the root link is in
    the world box and not flying off (``Session.advance``'s cheap check);
  * the input events a replay hands it that fall at the step (``n_ev``: mouse moves
    and sticks, ``session.event_runs``): each one's plain maps (clamped, linear: the
    runtime's ``maps._plain_run``, the same operations) written as rest angles, its
    frame maps' (the same arithmetic: ``maps._compile_frame``) as a held frame
    target's new angle (``m_frame``: its row in ``f_*``), solved at once, and a
    mouse move's values into ``in_val``, the device inputs a condition reads
    (``PK_S_INPUT``: a state polling the mouse); the first it is not given the maps of
    (kind -1, or its kind's rows -1) ends the call there, for Python to apply;
  * at a control step (``every``), the state's polled transitions, and at every step
    a running sequence's ``until`` (``SequenceController.tick``), each from its own
    first step (its ``after``): a transition holds when all its conditions do, a range
    condition when ``lo < value < hi``, an ``is`` when ``(value > 0.5) == want``, and
    with a ``for`` once they have held that many steps since the first poll that found
    them true (``since``, handed back: ``StateMachine.due``'s ``_since``), on the
    sensors ``conditions`` reads: a link's contact, its world angle within a turn, a
    joint's angle, a link's spin, its height;
  * then the travelling targets of a blend (``BlendController._write``: the eased
    value, smoothstep, written as the servo's rest angle, or a frame target's angle),
    the held frame targets (``FrameTargets.tick``: each joint's target re-solved from
    the links' angles of now by ``pk_frame``, the world-held and the relative ones, a
    travelling one at its eased angle), and feedback's add maps.

With ``tick_first`` it does the tick at ``now`` too: the call goes on from where
the last one stopped at its end (an input event came there, which changed nothing
the table holds: ``PollPlan.ready`` makes it again). It returns the step at which
Python takes over: the first where a transition holds
or the frame check fails (before any of that step's writes: the Python tick does them
and goes on exactly as if it had run every step), or ``stop``. A sensor does not read
a servo's target, so reading the conditions before the writes gives what the tick's
order gives. ``interface.poll_plan`` builds the table, and only for what it can
express; everything else stays on Python's path. Written operation for operation as
the Python it replaces (see ``kernel_source``), so the hashes are the same either way.
"""

POLL_TYPES = """
typedef struct {
    int n_trans;
    int *first;       /* per transition: the first step it is polled (entered + after) */
    int *period;      /* polled at steps that are multiples of it (a sequence's: 1) */
    int *hold;        /* the steps its `for` asks (0: none) */
    int *since;       /* the step its conditions began to hold (-1: they do not) */
    int *cond0, *n_cond;  /* its conditions: [cond0, cond0 + n_cond) */
    int *kind;        /* per condition: its sensor (PK_S_*: kernel_control) */
    void **body_a, **body_b;  /* the link (a joint's child), a joint's parent */
    double *lo, *hi;
    int *want;        /* -1: lo < value < hi; 0 or 1: an ``is`` */
    int n_blend;
    void **spring;    /* per travelling joint: its damped rotary spring (NULL: a frame
                         target's angle travels, held by the frame loop below) */
    double *start, *to;
    int *b_first, *b_last;
    double *b_value;  /* the value each wrote at the last control step */
    int n_frame;      /* per held frame target (FrameTargets.held, in its order): */
    void **f_parent, **f_child, **f_ref, **f_spring;  /* pk_frame's arguments */
    double *f_angle;
    int *f_hold_parent;
    int *f_blend;     /* -1, or the travelling joint whose value is its angle */
    int writes;       /* control steps the loop wrote at (this call) */
    pk_feedback *feedback;  /* NULL, or Feedback's add maps (pk_feedback_tick's) */
    int fb_ticks;     /* control steps the kernel ran them at (this call) */
    void **com_bodies;  /* the centre of mass (pk_com's arguments) */
    double *com_mass, *com_gx, *com_gy;
    int com_n;
    double com_total, gravity;  /* gravity: -space.gravity.y, for com.fall_time */
    int every, frame_every;
    void *root;
    double x0, x1, y0, y1, max_speed2;
    int n_ev;         /* input events to apply at their steps (0: none; pk_events) */
    int ev_done;      /* how many the call applied (handed back) */
    int *ev_step, *ev_kind;  /* per event: its step, its kind (-1: Python's) */
    double *ev_v;     /* per event: its two values (x, y; a stick's value) */
    int n_kind;       /* per kind: its map rows [k_first, k_last) (-1: Python's) */
    int *k_first, *k_last;
    int *m_use;       /* per map row: which of its event's values it reads */
    double *m_x0, *m_inv, *m_lo, *m_span, *m_gain;
    void **m_spring;
    int *m_frame;     /* per map row: -1, or the held frame target (f_*) it holds */
    double in_val[4]; /* the device inputs its conditions read (PK_S_INPUT + slot):
                         mouse.x, mouse.y, pointer.x, pointer.y; a mouse event sets them */
    int n_reach;      /* running two-link reaches (ReachController.tick), at every step: */
    void *r_parent[4], *r_goal[4];  /* pk_reach_aim's bodies (r_goal NULL: a world point) */
    double r_ax[4], r_ay[4], r_gx[4], r_gy[4], r_p0x[4], r_p0y[4], r_steps[4];
    int r_start[4];
    const double *r_params[4];  /* pk_reach_set's: the chain's numbers, its springs */
    void *r_spring0[4], *r_spring1[4];
    int r_own1[4];
    void *r_end[4];   /* the chain's end link (NULL: no grasp to try) */
    double r_ex[4], r_ey[4], r_tol[4];  /* its end point (the link's), the tolerance */
    double r_out[16], r_q[2];  /* (scratch: the aims, the solve) */
    int n_armed;      /* armed grasps (GraspController.tick), tried at every step: */
    void *a_end[4];   /* the chain's end link, its end point, the tolerance */
    double a_ex[4], a_ey[4], a_tol[4];
    int a_skip[4];    /* a place near where it let go is skipped (released_point) */
    double a_sx[4], a_sy[4];
    int a_p0[4], a_p1[4], a_s0[4], a_s1[4];  /* its places: [a_p0, a_p1), [a_s0, a_s1) */
    double a_px[64], a_py[64];  /* world points */
    double a_sax[64], a_say[64], a_svx[64], a_svy[64], a_svv[64];  /* segments */
} pk_poll_plan;
"""

POLL_CDEF = POLL_TYPES + """
void pk_poll_init(void *step);
double pk_hypot(double a, double b);
int pk_poll(void *space, double dt, int now, int stop, pk_poll_plan *p, int tick_first);
"""

POLL_SOURCE = "#include <float.h>\n" + POLL_TYPES + r"""
static void (*space_step)(void *, double);

void pk_poll_init(void *step)
{
    space_step = (void (*)(void *, double))step;
}

typedef struct { int done; double v[4]; } pk_com_now;  /* x, y, vx, vy, once a tick */

/* conditions.reader's value of a sensor (``kind``, on a and b) */
#define PK_S_INPUT 100  /* + a slot of in_val: a device input (conditions' input.NAME) */

static double pk_value(const pk_poll_plan *p, int kind, void *a, void *b, pk_com_now *com)
{
    if (kind >= PK_S_INPUT)
        return p->in_val[kind - PK_S_INPUT];
    if (PK_S_COM(kind) && !com->done) {  /* Character.com and com_velocity (pk_com) */
        pk_com(p->com_bodies, p->com_mass, p->com_gx, p->com_gy, p->com_n, p->com_total,
               com->v);
        com->done = 1;
    }
    if (kind == PK_S_COM_SPIN)  /* com.spin (Character.com_spin) */
        return pk_spin_about(p->com_bodies, p->com_mass, p->com_gx, p->com_gy, p->com_n,
                             com->v);
    return pk_sensor(kind, a, b, com->v, p->gravity);
}

/* StateMachine.due at a control step: does any polled transition hold at ``s``? */
static int pk_fires(pk_poll_plan *p, int s, pk_com_now *com)
{
    for (int k = 0; k < p->n_trans; k++) {
        int holds = 1;
        if (s < p->first[k] || s % p->period[k])
            continue;
        for (int i = p->cond0[k]; i < p->cond0[k] + p->n_cond[k] && holds; i++) {
            double v = pk_value(p, p->kind[i], p->body_a[i], p->body_b[i], com);
            if (p->want[i] < 0)
                holds = p->lo[i] < v && v < p->hi[i];
            else
                holds = (v > 0.5) == (p->want[i] != 0);
        }
        if (p->hold[k] == 0) {
            if (holds)
                return 1;
        } else if (holds) {  /* `for`: held since the first poll that found it true */
            if (p->since[k] < 0)
                p->since[k] = s;
            if (s - p->since[k] >= p->hold[k])
                return 1;
        } else {
            p->since[k] = -1;
        }
    }
    return 0;
}

/* CPython 3.11's math.hypot of two finite or not numbers (mathmodule.c's
   vector_norm, with its double-length helpers): not libm's, so the bits are Python's */
typedef struct { double hi, lo; } pk_dl;

static pk_dl pk_dl_split(double x)
{
    double t = x * 134217729.0;
    double hi = t - (t - x);
    pk_dl r = {hi, x - hi};
    return r;
}

static pk_dl pk_dl_mul(double x, double y)
{
    pk_dl xx = pk_dl_split(x), yy = pk_dl_split(y);
    double p = xx.hi * yy.hi;
    double q = xx.hi * yy.lo + xx.lo * yy.hi;
    double z = p + q;
    pk_dl r = {z, p - z + q + xx.lo * yy.lo};
    return r;
}

static pk_dl pk_dl_fast_sum(double a, double b)
{
    double x = a + b;
    double z = x - a;
    pk_dl r = {x, b - z};
    return r;
}

static double pk_norm(int n, double *vec, double max, int found_nan)
{
    double x, h, scale, csum = 1.0, frac1 = 0.0, frac2 = 0.0;
    pk_dl pr, sm;
    int max_e;
    if (isinf(max))
        return max;
    if (found_nan)
        return NAN;
    if (max == 0.0 || n <= 1)
        return max;
    frexp(max, &max_e);
    if (max_e < -1023) {
        for (int i = 0; i < n; i++)
            vec[i] /= DBL_MIN;
        return DBL_MIN * pk_norm(n, vec, max / DBL_MIN, found_nan);
    }
    scale = ldexp(1.0, -max_e);
    for (int i = 0; i < n; i++) {
        x = vec[i];
        x *= scale;
        pr = pk_dl_mul(x, x);
        sm = pk_dl_fast_sum(csum, pr.hi);
        csum = sm.hi;
        frac1 += pr.lo;
        frac2 += sm.lo;
    }
    h = sqrt(csum - 1.0 + (frac1 + frac2));
    pr = pk_dl_mul(-h, h);
    sm = pk_dl_fast_sum(csum, pr.hi);
    csum = sm.hi;
    frac1 += pr.lo;
    frac2 += sm.lo;
    x = csum - 1.0 + (frac1 + frac2);
    h += x / (2.0 * h);
    return h / scale;
}

double pk_hypot(double a, double b)
{
    double v[2] = {fabs(a), fabs(b)}, max = 0.0;
    int found_nan = 0;
    for (int i = 0; i < 2; i++) {
        found_nan |= isnan(v[i]);
        if (v[i] > max)
            max = v[i];
    }
    return pk_norm(2, v, max, found_nan);
}

/* props._outside: the parameter nearest u of a segment's point at least r from
   (cx, cy); 0 when the whole segment is within r (else 1, *u set) */
static int pk_outside(double *u, double ax, double ay, double vx, double vy, double vv,
                      double cx, double cy, double r)
{
    double dx = ax - cx, dy = ay - cy;
    if (pow(dx + *u * vx, 2.0) + pow(dy + *u * vy, 2.0) >= r * r)
        return 1;
    double b = (dx * vx + dy * vy) / vv;
    double c = (dx * dx + dy * dy - r * r) / vv;
    double m = b * b - c;
    double root = sqrt(m > 0.0 ? m : 0.0);  /* math.sqrt(max(0.0, ...)) */
    double inside[2] = {-b - root, -b + root}, best = 0.0, key = 0.0;
    int found = 0;
    for (int i = 0; i < 2; i++) {
        double t = inside[i];
        if (0.0 <= t && t <= 1.0) {  /* min(allowed, key=abs(s - u)): the first least */
            double k = fabs(t - *u);
            if (!found || k < key) {
                best = t; key = k; found = 1;
            }
        }
    }
    if (found)
        *u = best;
    return found;
}

/* GraspController.tick's test for armed grasp ``j`` (try_grasp: the nearest of its
   places, Prop.nearest's arithmetic, or its world points, within the tolerance): 1
   when one of its places is within it, or nearly (Python's tick then grasps or finds
   it does not). A place surely farther (its squared distance, or its segment's
   ignoring the skipped part, beyond the tolerance by far more than any rounding) is
   not worked out further. */
static int pk_catches(const pk_poll_plan *p, int j)
{
    pk_vect local = {p->a_ex[j], p->a_ey[j]};
    pk_vect e = to_world(p->a_end[j], local);
    double wx = e.x, wy = e.y, r = p->a_tol[j];
    double reach = r * (1.0 + 1e-9) + 1e-12, far = r * (1.0 + 1e-6) + 1e-9;
    double cx = p->a_sx[j], cy = p->a_sy[j];
    int skip = p->a_skip[j];
    far *= far;
    for (int i = p->a_p0[j]; i < p->a_p1[j]; i++) {
        double px = p->a_px[i], py = p->a_py[i];
        double dx = px - wx, dy = py - wy;
        if (dx * dx + dy * dy > far)
            continue;
        if (skip && pk_hypot(px - cx, py - cy) < r)
            continue;
        if (!(pk_hypot(dx, dy) > reach))
            return 1;
    }
    for (int i = p->a_s0[j]; i < p->a_s1[j]; i++) {
        double ax = p->a_sax[i], ay = p->a_say[i], vx = p->a_svx[i], vy = p->a_svy[i];
        double vv = p->a_svv[i];
        double u = ((wx - ax) * vx + (wy - ay) * vy) / vv;
        double m = u > 0.0 ? u : 0.0;
        u = m < 1.0 ? m : 1.0;
        double dx = ax + u * vx - wx, dy = ay + u * vy - wy;
        if (dx * dx + dy * dy > far)  /* (the segment's nearest: the skipped part's
                                          points are no nearer) */
            continue;
        if (skip && !pk_outside(&u, ax, ay, vx, vy, vv, cx, cy, r))
            continue;
        if (!(pk_hypot(ax + u * vx - wx, ay + u * vy - wy) > reach))
            return 1;
    }
    return 0;
}

/* The running reaches at ``s`` (ReachController.tick's fast path): each one's aim;
   1 when one would grasp (its end within its tolerance of the goal: try_grasp's
   test, met or nearly) or there is no kernel's hypot to trust (then Python's tick at
   ``s`` does it all, nothing written here); else each one's solve and writes, in
   the reaches' order */
static int pk_reaches(pk_poll_plan *p, int s)
{
    for (int j = 0; j < p->n_armed; j++)  /* (the armed grasps: Python's, if one holds) */
        if (pk_catches(p, j))
            return 1;
    for (int j = 0; j < p->n_reach; j++) {
        double *out = p->r_out + 4 * j;
        pk_reach_aim((double)(s - p->r_start[j]), p->r_parent[j], p->r_ax[j], p->r_ay[j],
                     p->r_goal[j], p->r_gx[j], p->r_gy[j], p->r_p0x[j], p->r_p0y[j],
                     p->r_steps[j], out);
        if (p->r_end[j]) {  /* try_grasp: hypot(end - goal) <= tolerance, with a margin */
            pk_vect local = {p->r_ex[j], p->r_ey[j]};
            pk_vect e = to_world(p->r_end[j], local);
            double d = pk_hypot(e.x - out[2], e.y - out[3]);
            if (!(d > p->r_tol[j] * (1.0 + 1e-9) + 1e-12))
                return 1;
        }
    }
    for (int j = 0; j < p->n_reach; j++) {
        double *out = p->r_out + 4 * j;
        pk_reach_set(p->r_params[j], out[0], out[1], pk_hypot(out[0], out[1]),
                     p->r_spring0[j], p->r_spring1[j], p->r_own1[j], p->r_q);
    }
    return 0;
}

/* the tick at ``s``: 1 when a transition holds or a reach grasps (nothing written) */
static int pk_tick(pk_poll_plan *p, int s)
{
    pk_com_now com = {0, {0.0, 0.0, 0.0, 0.0}};
    if (pk_fires(p, s, &com))
        return 1;
    if ((p->n_reach || p->n_armed) && pk_reaches(p, s))
        return 1;
    if (s % p->every)
        return 0;
    p->writes++;
    for (int j = 0; j < p->n_blend; j++) {  /* BlendController._write, none arrived */
        double u = (double)(s - p->b_first[j]) / (double)(p->b_last[j] - p->b_first[j]);
        u = u * u * (3.0 - 2.0 * u);
        p->b_value[j] = p->start[j] + (p->to[j] - p->start[j]) * u;
        if (p->spring[j])
            set_rest_angle(p->spring[j], p->b_value[j]);
    }
    /* FrameTargets.tick: each held joint re-solved, a travelling one at the angle the
       blend holds it at now (its hold, solved at once, wrote what this writes) */
    for (int j = 0; j < p->n_frame; j++)
        pk_frame(p->f_parent[j], p->f_child[j], p->f_ref[j],
                 p->f_blend[j] < 0 ? p->f_angle[j] : p->b_value[p->f_blend[j]],
                 p->f_hold_parent[j], p->f_spring[j]);
    if (p->feedback) {  /* Feedback.tick: pk_feedback_tick, the centre of mass shared */
        pk_feedback_add(p->feedback, com.v, &com.done);
        p->fb_ticks++;
    }
    return 0;
}

/* The input events due at ``s`` (a mouse move, a stick), their maps as the runtime's
   plain maps write them (maps._plain_run: one joint, clamped, linear): 1 when one is
   not this call's to apply (Python applies it, and what comes after it) */
static int pk_events(pk_poll_plan *p, int s)
{
    while (p->ev_done < p->n_ev && p->ev_step[p->ev_done] == s) {
        int e = p->ev_done, kind = p->ev_kind[e];
        if (kind < 0 || kind >= p->n_kind || p->k_first[kind] < 0)
            return 1;
        if (kind == 0) {  /* a mouse move: the inputs it sets (runtime.on_event's) */
            p->in_val[0] = p->in_val[2] = p->ev_v[2 * e];
            p->in_val[1] = p->in_val[3] = p->ev_v[2 * e + 1];
        }
        for (int m = p->k_first[kind]; m < p->k_last[kind]; m++) {
            double u = (p->ev_v[2 * e + p->m_use[m]] - p->m_x0[m]) * p->m_inv[m];
            int f = p->m_frame ? p->m_frame[m] : -1;
            u = u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u);
            if (f < 0) {
                set_rest_angle(p->m_spring[m], p->m_gain[m] * (p->m_lo[m] + u * p->m_span[m]));
            } else {  /* a frame map: the joint held at its new angle, solved at once
                         (FrameTargets.holder's hold_at), then at the control steps */
                p->f_angle[f] = p->m_gain[m] * (p->m_lo[m] + u * p->m_span[m]);
                pk_frame(p->f_parent[f], p->f_child[f], p->f_ref[f], p->f_angle[f],
                         p->f_hold_parent[f], p->f_spring[f]);
            }
        }
        p->ev_done++;
    }
    return 0;
}

/* ``tick_first``: the tick at ``now`` too (else Python's tick has run there) */
int pk_poll(void *space, double dt, int now, int stop, pk_poll_plan *p, int tick_first)
{
    int s = now;
    p->fb_ticks = p->writes = p->ev_done = 0;
    if (tick_first && pk_tick(p, s))
        return s;
    for (;;) {
        space_step(space, dt);
        s++;
        if (s >= stop)
            return s;
        if (s % p->frame_every == 0) {  /* Session.advance's frame check */
            pk_vect q = get_position(p->root), v;
            if (!(p->x0 < q.x && q.x < p->x1 && p->y0 < q.y && q.y < p->y1))
                return s;
            v = get_velocity(p->root);
            if (!(v.x * v.x + v.y * v.y < p->max_speed2))
                return s;
        }
        if (p->n_ev && pk_events(p, s))  /* (the events at ``s`` come before its tick) */
            return s;
        if (pk_tick(p, s))
            return s;
    }
}
"""
