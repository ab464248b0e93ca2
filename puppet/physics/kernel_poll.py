"""The compiled kernel's stepping loop (``pk_poll``): Chipmunk's step, and between the
steps what a state that polls at the control rate does in Python, for as long as
nothing else is due.

A state machine polling every step (a state's ``control_rate: 480``) costs a Luxo
step, 2.3 us of physics, another 1.5-2 us of Python: a tick, the poll (a contact read,
an angle) and a blend's eased target. ``pk_poll`` steps the space from ``now`` and,
after each step, does the work ``Session.advance`` would do there, in its order:

  * at a frame's end (``frame_every``), the session's check that the root link is in
    the world box and not flying off (``Session.advance``'s cheap check);
  * at a control step (``every``), the state's polled transitions, and at every step
    a running sequence's ``until`` (``SequenceController.tick``), each from its own
    first step (its ``after``): a transition holds when all its conditions do, a range
    condition when ``lo < value < hi``, an ``is`` when ``(value > 0.5) == want``, and
    with a ``for`` once they have held that many steps since the first poll that found
    them true (``since``, handed back: ``StateMachine.due``'s ``_since``), on the
    sensors ``conditions`` reads: a link's contact, its world angle within a turn, a
    joint's angle, a link's spin, its height;
  * then the travelling targets of a blend (``BlendController._write``: the eased
    value, smoothstep, written as the servo's rest angle).

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
    int *kind;        /* per condition: 0 contact, 1 angle within a turn, 2 joint, 3 spin,
                         4 height (of the link's centre of mass), 5 com.fall_time,
                         6 com.x, 7 com.y, 8 com.vx, 9 com.vy */
    void **body_a, **body_b;  /* the link (a joint's child), a joint's parent */
    double *lo, *hi;
    int *want;        /* -1: lo < value < hi; 0 or 1: an ``is`` */
    int n_blend;
    void **spring;    /* per travelling joint: its damped rotary spring */
    double *start, *to;
    int *b_first, *b_last;
    int n_read;       /* feedback: the sensors its maps read, in file units */
    int *r_kind;
    void **r_a, **r_b;
    double *r_scale;  /* 180 / pi for an angle's degrees, 0: as read */
    double *sampled;  /* what each read last (handed back: the runtime's inputs) */
    int n_add;        /* its add maps' terms, in file order: joint += gain * value */
    int *a_read, *a_joint, *a_clamp;  /* a_read -1: a constant term (``add:``) */
    double *a_x0, *a_inv, *a_lo, *a_span, *a_gain;
    int n_fb;         /* the joints they add to, with the base and the last written */
    void **f_spring;
    double *f_base, *f_last, *f_sum;
    int *f_has;
    int fb_ticks;     /* control steps the kernel ran the maps at (this call) */
    void **com_bodies;  /* the centre of mass (pk_com's arguments) */
    double *com_mass, *com_gx, *com_gy;
    int com_n;
    double com_total, gravity;  /* gravity: -space.gravity.y, for com.fall_time */
    int every, frame_every;
    void *root;
    double x0, x1, y0, y1, max_speed2;
} pk_poll_plan;
"""

POLL_CDEF = POLL_TYPES + """
void pk_poll_init(void *step, void *local_to_world, void *get_cog, void *get_rest);
int pk_poll(void *space, double dt, int now, int stop, pk_poll_plan *p, int tick_first);
"""

POLL_SOURCE = POLL_TYPES + r"""
static void (*space_step)(void *, double);
static pk_vect (*local_to_world)(void *, pk_vect);
static pk_vect (*get_cog)(void *);
static double (*get_rest_angle)(void *);

void pk_poll_init(void *step, void *to_world, void *cog, void *rest)
{
    space_step = (void (*)(void *, double))step;
    local_to_world = (pk_vect (*)(void *, pk_vect))to_world;
    get_cog = (pk_vect (*)(void *))cog;
    get_rest_angle = (double (*)(void *))rest;
}

typedef struct { int done; double v[4]; } pk_com_now;  /* x, y, vx, vy, once a tick */

static void pk_touched(void *body, void *arbiter, void *data)
{
    (void)body; (void)arbiter;
    *(int *)data = 1;
}

/* conditions.reader's value of a sensor (``kind``, on a and b) */
static double pk_value(const pk_poll_plan *p, int kind, void *a, void *b, pk_com_now *com)
{
    int touching;
    double y, vy;
    if (kind >= 5 && !com->done) {  /* Character.com and com_velocity (pk_com) */
        pk_com(p->com_bodies, p->com_mass, p->com_gx, p->com_gy, p->com_n, p->com_total,
               com->v);
        com->done = 1;
    }
    switch (kind) {
    case 0:
        touching = 0;
        each_arbiter(a, pk_touched, &touching);
        return touching ? 1.0 : 0.0;
    case 1:
        return remainder(get_angle(a), TURN);
    case 2:
        return get_angle(a) - get_angle(b);
    case 3:
        return get_spin(a);
    case 4:  /* Character.link_position's y */
        return local_to_world(a, get_cog(a)).y;
    case 5:  /* conditions._fall_time */
        y = com->v[1];
        if (y <= 0.0)
            return 0.0;
        if (p->gravity <= 0.0)
            return INFINITY;
        vy = com->v[3];
        return (vy + sqrt(vy * vy + 2.0 * p->gravity * y)) / p->gravity;
    default:
        return com->v[kind - 6];
    }
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

/* the tick at ``s``: 1 when a transition holds (nothing written) */
static int pk_tick(pk_poll_plan *p, int s)
{
    pk_com_now com = {0, {0.0, 0.0, 0.0, 0.0}};
    if (pk_fires(p, s, &com))
        return 1;
    if (s % p->every)
        return 0;
    for (int j = 0; j < p->n_blend; j++) {  /* BlendController._write, none arrived */
        double u = (double)(s - p->b_first[j]) / (double)(p->b_last[j] - p->b_first[j]);
        u = u * u * (3.0 - 2.0 * u);
        set_rest_angle(p->spring[j], p->start[j] + (p->to[j] - p->start[j]) * u);
    }
    if (p->n_read == 0 && p->n_add == 0)
        return 0;
    /* Feedback.tick: the sensors (Character.sample: the centre of mass once), then the
       add maps' sums (maps.compile_contribution), added to each joint's base */
    for (int r = 0; r < p->n_read; r++) {
        double v = pk_value(p, p->r_kind[r], p->r_a[r], p->r_b[r], &com);
        p->sampled[r] = p->r_scale[r] != 0.0 ? v * p->r_scale[r] : v;
    }
    for (int j = 0; j < p->n_fb; j++)
        p->f_sum[j] = 0.0;
    for (int t = 0; t < p->n_add; t++) {
        double v, u;
        if (p->a_read[t] < 0) {
            v = p->a_gain[t];
        } else {
            u = (p->sampled[p->a_read[t]] - p->a_x0[t]) * p->a_inv[t];
            if (p->a_clamp[t])
                u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
            v = p->a_gain[t] * (p->a_lo[t] + u * p->a_span[t]);
        }
        p->f_sum[p->a_joint[t]] = p->f_sum[p->a_joint[t]] + v;
    }
    for (int j = 0; j < p->n_fb; j++) {
        double now = get_rest_angle(p->f_spring[j]);
        double b = p->f_has[j] && now == p->f_last[j] ? p->f_base[j] : now;
        p->f_base[j] = b;
        p->f_last[j] = b + p->f_sum[j];
        p->f_has[j] = 1;
        set_rest_angle(p->f_spring[j], p->f_last[j]);
    }
    p->fb_ticks++;
    return 0;
}

/* ``tick_first``: the tick at ``now`` too (else Python's tick has run there) */
int pk_poll(void *space, double dt, int now, int stop, pk_poll_plan *p, int tick_first)
{
    int s = now;
    p->fb_ticks = 0;
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
        if (pk_tick(p, s))
            return s;
    }
}
"""
