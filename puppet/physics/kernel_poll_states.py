"""The C of a state machine's transitions inside ``pk_poll``'s loop (``kernel_poll``):
a transition that holds, into a state whose entry only starts plain targets travelling
(``set`` with ``over``) or does nothing, entered between Chipmunk's steps, and the
blend's arrivals, instead of stopping the loop for Python's tick at each.

On Luxo a state polled every step (``control_rate: 480``) that ends in a transition
cost a Python tick, the poll plan's ``ready`` and a new call (30-45 us, as much as 15
physics steps): the shuffle's 132 ticks a replay were most of its overhead. The Python
it mirrors: ``InterfaceRuntime.tick`` at a step where a transition holds (the
controllers' writes first: ``BlendController._write``, an arrival writing ``to`` and
letting the joint go; then ``StateMachine.due``, ``_enter_state``, the entry's
``BlendController.start``: each joint from its spring's rest angle now, to its target,
over ``max(1, steps)`` steps; then ``due`` again at the same step, chained up to
``MAX_CHAINED_GOTOS`` entries). Each entry and arrival is logged (``l_*``) for
``interface.poll_states`` to hand back to the runtime after the call, in order, as
Python's ticks would have left it. A transition into a state it cannot enter
(``r_target`` -1) ends the call there for Python's tick, as before. Kept in its own
module: it reads ``pk_poll_plan`` (``POLL_TYPES``).
"""

from puppet.physics.kernel_poll_feed import FEED_SOURCE
from puppet.physics.kernel_poll_poses import KEPT_SOURCE, POSES_SOURCE

STATES_TYPES = """
typedef struct {  /* a machine's states, for pk_poll's transitions (poll_states) */
    int max_chain;        /* MAX_CHAINED_GOTOS */
    int *t0, *t1;         /* per state: its transitions' rows [t0, t1) */
    int *r_after, *r_period, *r_target, *r_cond0, *r_ncond;  /* per row (target -1:
                             Python's; ncond 0: a timer) */
    int *r_hold;          /* per row: its `for` in steps (0: none; since handed back) */
    int *c_kind;          /* per condition: as the plan's */
    void **c_a, **c_b;
    double *c_lo, *c_hi;
    int *c_want;
    int *e0, *e1;         /* per state: its entry's targets [e0, e1) */
    void **e_spring;
    double *e_to;
    int *e_steps;
    int *e_every;         /* per state: its control period (_follow_rate's, one machine) */
    int *p_target;        /* per plan transition (the state's now): its state, or -1 */
    int *b_live;          /* per plan blend row: travelling (0: arrived) */
    int max_blend, max_trans, max_cond;
    int n_log, max_log;   /* what the call did, in order: per entry its step, its kind */
    int *l_step, *l_kind, *l_arg;  /* (0: the blend row arg arrived; 1: state arg
                             entered, its targets' starts from l_val[l_val0]) */
    int *l_val0;
    double *l_val;
    int n_val, max_val;
    int started;          /* the step an entry last started targets travelling */
    int *w0, *w1;         /* per state: its entry's pose writes [w0, w1) (poll_poses) */
    void **w_spring;
    int *w_what;          /* 0 a target, 1 a stiffness, 2 a torque cap */
    double *w_value;
    void *f_stiffness, *f_max_force;  /* pymunk's setters (kernel_poll_poses) */
    int n_state;          /* the states; rows w0[n_state + b]: b's kept press's writes */
    int *k_goto, *k_window;  /* per state: a kept press acts as it is entered: its
                             binding's state, or -1; the buffer in steps */
    int kept_at, kept_live;  /* the press's step; 1 until the loop spends it */
    int fb_on;            /* feedback's add maps follow the states (kernel_poll_feed): */
    pk_feedback **e_fb;   /* per state: its maps' rows (NULL: none), into p->feedback */
    int fb_state, fb_ran, fb_at;  /* the state whose rows p->feedback has, whether they
                             ran since it was entered, the step of a tick's add made
                             before its entries (pk_transit) */
} pk_states;
"""

STATES_SOURCE = POSES_SOURCE + r"""
static int pk_log(pk_states *st, int s, int kind, int arg)
{
    int n = st->n_log++;
    st->l_step[n] = s;
    st->l_kind[n] = kind;
    st->l_arg[n] = arg;
    st->l_val0[n] = st->n_val;
    return n;
}
""" + FEED_SOURCE + r"""

/* BlendController._write at ``s``: the travelling targets, an arrived one written at
   its ``to`` and let go (logged) */
static void pk_blend_write(pk_poll_plan *p, int s)
{
    pk_states *st = p->states;
    for (int j = 0; j < p->n_blend; j++) {
        if (st && !st->b_live[j])
            continue;
        double u = (double)(s - p->b_first[j]) / (double)(p->b_last[j] - p->b_first[j]);
        if (s >= p->b_last[j])
            u = 1.0;
        else
            u = u * u * (3.0 - 2.0 * u);
        p->b_value[j] = p->start[j] + (p->to[j] - p->start[j]) * u;
        if (p->spring[j])
            set_rest_angle(p->spring[j], p->b_value[j]);
        if (st && s >= p->b_last[j]) {
            st->b_live[j] = 0;
            pk_log(st, s, 0, j);
        }
    }
}

/* an arrival due at ``s`` (BlendController.tick between control steps) */
static int pk_arriving(pk_poll_plan *p, int s)
{
    for (int j = 0; j < p->n_blend; j++)
        if (p->states->b_live[j] && s >= p->b_last[j])
            return 1;
    return 0;
}

/* room for a tick's entries and arrivals, else Python's tick */
static int pk_room(pk_poll_plan *p, pk_states *st)
{
    return st->n_log + p->n_blend + 2 * st->max_chain + 1 <= st->max_log
        && st->n_val + st->max_chain * p->n_blend + 64 <= st->max_val;
}

/* _enter_state of ``b`` at ``s`` (its entry a plain blend, a pose or nothing): 0 when
   it does not fit the plan's rows (nothing done: Python's) */
static int pk_enter(pk_poll_plan *p, pk_states *st, int b, int s)
{
    int k = 0, i = 0, n = 0;
    for (int j = 0; j < p->n_blend; j++)  /* rows in use */
        n += st->b_live[j];
    for (int e = st->e0[b]; e < st->e1[b]; e++) {  /* a joint not travelling: a row more */
        int j = 0;
        while (j < p->n_blend && !(st->b_live[j] && p->spring[j] == st->e_spring[e]))
            j++;
        n += j == p->n_blend;
    }
    if (n > st->max_blend || st->t1[b] - st->t0[b] > st->max_trans)
        return 0;
    for (int r = st->t0[b]; r < st->t1[b]; r++)
        i += st->r_ncond[r];
    if (i > st->max_cond || !pk_pose_fits(p, st, b))
        return 0;
    /* _enter_state's order: the machine's state, _follow_rate, _refresh_active_maps,
       the entry (its pose, its blend); the rows left logged before the state entered,
       so that the entry's log is the last (pk_enter_kept) */
    p->every = st->e_every[b];  /* _follow_rate: the machine's, the blend's, feedback's */
    if (st->fb_on)  /* _refresh_active_maps: Feedback.set_maps (kernel_poll_feed) */
        pk_feed_enter(p, st, b, s);
    pk_log(st, s, 1, b);
    pk_pose_write(st, b);  /* (a pose's entry: kernel_poll_poses) */
    for (int e = st->e0[b]; e < st->e1[b]; e++) {  /* BlendController.start */
        int j = 0, steps = st->e_steps[e];
        double from = get_rest_angle(st->e_spring[e]);
        while (j < p->n_blend && !(st->b_live[j] && p->spring[j] == st->e_spring[e]))
            j++;
        if (j == p->n_blend) {  /* a new joint: the first free row, else one more */
            j = 0;
            while (j < p->n_blend && st->b_live[j])
                j++;
            if (j == p->n_blend)
                p->n_blend++;
        }
        st->started = s;
        p->spring[j] = st->e_spring[e];
        p->start[j] = from;
        p->to[j] = st->e_to[e];
        p->b_first[j] = s;
        p->b_last[j] = s + (steps > 1 ? steps : 1);
        st->b_live[j] = 1;
        st->l_val[st->n_val++] = from;
    }
    i = 0;
    for (int r = st->t0[b]; r < st->t1[b]; r++, k++) {  /* the state's table */
        p->first[k] = s + st->r_after[r];
        p->period[k] = st->r_period[r];
        p->hold[k] = st->r_hold[r];
        p->since[k] = -1;
        p->cond0[k] = i;
        p->n_cond[k] = st->r_ncond[r];
        st->p_target[k] = st->r_target[r];
        for (int c = st->r_cond0[r]; c < st->r_cond0[r] + st->r_ncond[r]; c++, i++) {
            p->kind[i] = st->c_kind[c];
            p->body_a[i] = st->c_a[c];
            p->body_b[i] = st->c_b[c];
            p->lo[i] = st->c_lo[c];
            p->hi[i] = st->c_hi[c];
            p->want[i] = st->c_want[c];
        }
    }
    p->n_trans = k;
    return 1;
}

""" + KEPT_SOURCE + r"""
/* A transition (plan row k - 1) holds at ``s``: the tick's writes, then its state and
   those chained after it at ``s`` entered; 1 when Python's tick must run at ``s``
   (a state it cannot enter: before any write, or after those it entered) */
static int pk_transit(pk_poll_plan *p, int s, int k, pk_com_now *com)
{
    pk_states *st = p->states;
    int b = st ? st->p_target[k - 1] : -1;
    if (b < 0 || !pk_room(p, st))
        return 1;
    if (s % p->every == 0 || pk_arriving(p, s))  /* (the controllers tick before the
                                                    machines: BlendController.tick) */
        pk_blend_write(p, s);
    if (st->fb_on && s % p->every == 0)  /* and Feedback.tick, with the rows of now */
        pk_feed_tick(p, st, s, com);
    for (int chain = 1;; chain++) {
        if (!pk_enter_kept(p, st, b, s))
            return 1;
        k = pk_fires(p, s, com);  /* StateMachine.due again, at the same step */
        if (!k || chain >= st->max_chain)
            return 0;
        b = st->p_target[k - 1];
        if (b < 0)
            return 1;
    }
}
"""
