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
    target's new angle (``m_frame``: its row in ``f_*``), solved at once, its pose
    grids (a cat's legs: ``maps._grid_run``'s ``pk_grid_run``, ``k_grid``) and a
    mouse move's values into ``in_val``, the device inputs a condition reads
    (``PK_S_INPUT``: a state polling the mouse); the first it is not given the maps of
    (kind -1, or its kind's rows -1) ends the call there, for Python to apply; a
    performer's sample (PK_EV_SAMPLE, ``pk_sample``) stores the tracker's values;
  * at a control step (``every``), the state's polled transitions, and at every step
    a running sequence's ``until`` (``SequenceController.tick``), each from its own
    first step (its ``after``): a transition holds when all its conditions do, a range
    condition when ``lo < value < hi``, an ``is`` when ``(value > 0.5) == want``, and
    with a ``for`` once they have held that many steps since the first poll that found
    them true (``since``, handed back: ``StateMachine.due``'s ``_since``), on the
    sensors ``conditions`` reads: a link's contact, its world angle within a turn, a
    joint's angle, a link's spin, its height;
  * a transition that holds into a state the plan's ``states`` table can enter (its
    entry a plain ``set`` with ``over``, or nothing; ``kernel_poll_states``): the
    tick's writes, the state's table and targets, the states chained after it, each
    logged for ``interface.poll_states`` to hand back; with the table the timers are
    rows without conditions, and the blend's arrivals are the loop's too;
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
and goes on exactly as if it had run every step), or ``stop``. Python's tick polls the
machines after its controllers' writes; here they come first. Most writes are servo
targets, which no sensor reads before the next step, so the order gives the same
readings; but ``pk_contacts`` changes every body's velocity, which the centre of
mass's velocity, fall time and spin read (``poll_track.VELOCITY``): a plan whose
machines read one of those (``c_late``) makes a tracker tick's contacts first, and
undoes them (the velocities saved) when the tick stops for Python. A sequence's
``until`` is polled before the controllers in both (poll_track: not with c_late).
``interface.poll_plan`` builds the table, and only for what it can
express; everything else stays on Python's path. Written operation for operation as
the Python it replaces (see ``kernel_source``), so the hashes are the same either way.
"""

from puppet.physics.kernel_poll_contact import CONTACT_SOURCE
from puppet.physics.kernel_poll_reach import REACH_SOURCE
from puppet.physics.kernel_poll_states import STATES_SOURCE, STATES_TYPES
from puppet.physics.kernel_poll_track import TRACK_SOURCE

POLL_TYPES = STATES_TYPES + """
typedef struct {  /* walking in place between samples (tracking_walk, track_poll) */
    double *frames;   /* the gait cycle's clip: n_frames frames of width values */
    int n_frames, width, xi;  /* xi: root.x's place in a frame */
    double a, b, start, stride;  /* GaitCycle's a, b, _raw_one(a, xi), stride */
    double *drift;
    int n_rows;       /* blend_into's rows read by the tracker: the value's index and */
    int *row_val, *row_ch;  /* the frame's */
    double dt, stop_after, blend;
    int walking, has_last_at, last_at, has_at, at;  /* WalkInPlace.walk's, */
    double phase, speed, travel, weight;             /* kept here during a run */
    int n_vals;       /* the performer's values (raw, raw_has) and the view's */
    double *raw, *view;
    char *raw_has, *view_has;  /* (raw_has NULL: all there) */
    int n_spans;      /* Simulation.ground_surface's spans: lo, hi, x0, y0, x1, y1, half */
    double *spans;
    int lift;         /* the feet stand on the ground (tracking.feet and a ground) */
    double extra;     /* the clearance, or -PRESS */
    pk_chain *feet;   /* a sample's step (pk_walk_step): the chain from the root to the
                         feet, its values the raw's places (NULL: no gap to read) */
    int f_root, f_angle, f_link[2];  /* the root link, root.angle's place, the feet */
    double f_gx[2], f_gy[2], *poses;  /* (their centres of gravity; pk_pose's out) */
    double f_lift, f_lo, f_hi, f_lifts[2];  /* walk_in_place's lift, steps, the cycle's */
    int last_side, has_period;       /* WalkInPlace.walk's (-1: None) */
    double period;
} pk_walk;

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
    int ev_at_stop;   /* ``stop`` a timer's or an arrival's step (Python's tick comes
                         there), before the call's end and the next history boundary:
                         the events at it applied first, as the session's loop would */
    int *ev_step, *ev_kind;  /* per event: its step, its kind (-1: Python's) */
    double *ev_v;     /* per event: its two values (x, y; a stick's value) */
    int n_kind;       /* per kind: its map rows [k_first, k_last) (-1: Python's) */
    int *k_first, *k_last;
    pk_grid_table **k_grid;  /* per kind: NULL, or its pose grids (pk_grid_run, after
                         its rows: they write other joints) on the event's two values */
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
    pk_track *track;  /* NULL, or KD tracking between a performer's samples: at the
                         steps t_phase + n * t_every, pk_targets and pk_track_pull */
    int t_phase, t_every, t_ticks;  /* (t_ticks: the ticks it ran, this call) */
    double *t_vals;   /* pk_targets' values, has, own; pk_track_pull's own, weight */
    char *t_has, *t_own, *t_rows;  /* (NULL: every value, joint, link) */
    double t_weight, t_period;
    int t_pose;       /* the first tick's a sample's: pk_track_pose with these first */
    int t_lift, t_vel;
    double t_x0, t_ground, t_extra, t_h;
    pk_walk *walk;    /* NULL, or the view walks in place: each tick's own (below) */
    int t_n;          /* the values */
    int t_mix, t_mix_at, t_mix_steps;  /* the view mixes t_came into t_vals (hold, back) */
    double *t_came; char *t_came_has;  /* (has NULL: all there) */
    double *t_view; char *t_view_has;
    double t_cl[2]; int t_cl_has[2];   /* the clearance: came's, the view's own */
    int t_soles;      /* the lift: the feet on the ground under the view (spans) */
    int n_spans;      /* Simulation.ground_surface's spans (7 a span) */
    double *spans;
    int t_last;       /* the step of the last tick it ran (this call) */
    int t_nopull;     /* the view lacks the root's place: the targets alone (_pull's) */
    int g_on, g_n, g_at;  /* getting up (tracking_getup.GetUp): g_n poses from g_at, */
    int *g_ends;      /* each reached at g_ends[i]; the values: came, then each pose's */
    double *g_vals; char *g_has;  /* ((g_n + 1) rows of t_n), their clearance: */
    double *g_cl; int *g_cl_has;
    int g_n_feel;     /* supported(): the feet and hands, one touching the ground */
    void **g_feel;
    double g_rise;
    int l_on, l_start, l_span, l_first, l_len;  /* a motion library's window followed
                         (tracking_library): from l_start, l_span frames from the clip's
                         l_first of its l_len (l_width values each) */
    int l_width, *l_col;  /* the value's column in a frame (-1: not a library channel) */
    double *l_frames, l_rate, l_duration, l_offset, l_blend, l_low, l_weight;
    int l_cl;         /* the clearance's column (-1) */
    int st_on, st_row, st_start;  /* a large push's protective step (Tracker.step) */
    double st_x0, st_y0, st_x1, st_y1, st_time, st_lift, st_low;
    int rx_on, rx_start, rx_done;  /* a reaction's weight (Tracker._weight): from rx_start, */
    double rx_dt, rx_weight, rx_hold, rx_recover;  /* rx_done: the step it ended (-1) */
    int c_n;          /* intentional contacts at the tracker's ticks (kernel_poll_contact, */
    void **c_body;    /* with t_nopull): per held hand its pin's body, and its row: the */
    double *c_row;    /* point on it, the contact's start (angle, length, the performer's
                         angle, length), the performer's vector and rates (10 values) */
    double c_swing, c_swing_d, c_spring, c_damp, c_mass, c_period;
    int c_late;       /* the machines read a velocity the contacts move: at a tracker's
                         tick, the contacts first (Python's order), undone if it stops */
    pk_states *states;  /* NULL, or transitions entered in the loop (kernel_poll_states) */
    int t_lost, t_sample;  /* an angles tracker's stream is lost at a tick more than
                         t_lost steps after its last sample (t_sample; t_lost 0: no check) */
    int ch_n, ch_t;   /* a performer's samples among the events (kind PK_EV_SAMPLE,
                         pk_sample): per event ch_n values (0: Python's), the first ch_t
                         for t_vals, the rest c_xy's */
    double *ch_v; char *ch_has;  /* (ch_has: the event has the value; 2: Python's) */
    int t_fresh;      /* a sample the run applied: the next tracker tick is a sample's */
    int t_prev;       /* KD: the sample the performed velocities were last taken at */
    int t_cl_sample;  /* KD: a sample's value after t_vals' is the clearance: the view's
                         too (t_cl[1]: a mix back to the performer, a library window) */
    double t_dt;      /* (pk_fresh: velocity_sample, the lift; c_xy[0]: the clearance) */
    double c_xy[8];   /* per contact: the performer's hand (x, y: the channels now), */
    double c_sv[8];   /* its vector at the last sample its rates were worked out at */
    int c_seen[4];    /* (IntentionalContacts.perf_turn's angle, length, step), */
    double c_dt;      /* per step (the rates: pk_contact_rates) */
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

""" + TRACK_SOURCE + r"""
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

/* StateMachine.due at a control step: does any polled transition hold at ``s``? (its
   row + 1, else 0) */
static inline __attribute__((always_inline))
int pk_fires(pk_poll_plan *p, int s, pk_com_now *com)
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
                return k + 1;
        } else if (holds) {  /* `for`: held since the first poll that found it true */
            if (p->since[k] < 0)
                p->since[k] = s;
            if (s - p->since[k] >= p->hold[k])
                return k + 1;
        } else {
            p->since[k] = -1;
        }
    }
    return 0;
}

""" + REACH_SOURCE + CONTACT_SOURCE + STATES_SOURCE + r"""
/* the tick at ``s``: 1 when a transition holds (one not the loop's to enter: nothing
   written) or a reach grasps */
static int pk_tick(pk_poll_plan *p, int s)
{
    pk_com_now com = {0, {0.0, 0.0, 0.0, 0.0}};
    pk_vect was[PK_LATE];
    if (p->t_lost && p->track && (s - p->t_phase) % p->t_every == 0
            && s - p->t_sample > p->t_lost)
        return 1;  /* (Tracker.tick: the stream lost here, Python's) */
    int late = p->c_late && p->track && p->c_n && (s - p->t_phase) % p->t_every == 0;
    if (late)  /* (Python's machines poll after the tracker's contacts: c_late; no
                  states entered in the loop with a tracker: poll_states.usable) */
        pk_contacts_first(p, &com, was);
    int fired = pk_fires(p, s, &com);
    if ((fired && pk_transit(p, s, fired, &com))
            || ((p->n_reach || p->n_armed) && pk_reaches(p, s))) {
        if (late)  /* (Python's tick does it all again) */
            pk_contacts_undo(p, was);
        return 1;
    }
    if (fired && p->states->fb_on) {  /* the tick's writes and add made before its
                                         entries (kernel_poll_feed): an entry's start
                                         writes every travelling target again */
        if (p->states->started == s)
            pk_blend_write(p, s);
        p->writes += s % p->every == 0;
        return 0;
    }
    if (p->track && (s - p->t_phase) % p->t_every == 0) {
        /* Tracker.tick (interface/track_poll.py): the joint targets of the view, the
           pose (its velocities from the last sample, with t_pose: a sample's tick),
           the pulls. Between samples without a walk the view is the same values and
           the pose the last one (pk_track_pose again would give the same targets);
           walking in place, the view walks on (at a sample Python advanced it). */
        int fresh = 0;
        if (p->t_fresh) {  /* a sample's tick (TrackPoll.ready's resume, in C) */
            p->t_fresh = 0;
            if (!p->t_nopull) {
                pk_fresh(p);
                fresh = 1;
            }
        }
        pk_walk *w = p->walk;
        const double *vals = p->t_vals;
        const char *has = p->t_has;
        int pose = p->t_pose, lift = p->t_lift, vel = 0, no_lift = 0;
        double l_weight = 1.0;
        double ground = p->t_ground, extra = p->t_extra, h = 0.0;
        if (w) {
            if (fresh)  /* (a sample's: its step read, then the advance) */
                pk_walk_step(w, s);
            else if (!pose)
                pk_walk_advance(w, s);
            pk_walk_view(w, p->t_x0, &ground, &lift);
            vals = w->view;
            has = w->raw_has ? w->view_has : 0;
            extra = lift ? w->extra : 0.0;
        } else if (p->t_mix || p->g_on || p->l_on) {  /* mix(came, the values,
                                       _fraction(s, at)), a get-up's poses, a window */
            double clearance;
            if (p->g_on)
                pk_getup(p, s, &clearance, &no_lift);
            else if (p->l_on)
                l_weight = pk_library(p, s, &clearance);
            else
                pk_mix(p, pk_fraction(s, p->t_mix_at, p->t_mix_steps), &clearance);
            vals = p->t_view;
            has = p->t_view_has;
            ground = 0.0;
            lift = 0;
            if (p->t_soles)
                ground = pk_ground(p->spans, p->n_spans, p->t_x0 + vals[0], &lift);
            extra = !lift ? 0.0 : clearance > 0.0 ? clearance : -0.003;  /* -PRESS */
            if (lift && p->g_on)
                lift = 2;  /* (every link's lowest points) */
        }
        double weight = p->l_on ? l_weight : p->rx_on ? pk_react_weight(p, s) : p->t_weight;
        pk_targets(p->track, vals, has, p->t_own);
        if (p->t_nopull) {  /* (a tracker's angles alone: poll_track, or the view lacks
                               the root's place) */
            if (p->c_n && !late)  /* (Tracker.tick: the contacts after the targets,
                                     which they do not read) */
                pk_contacts(p, &com);
            p->t_ticks++;
            p->t_last = s;
            goto control;
        }
        if (pose || w || p->t_mix || p->g_on || p->l_on) {
            if (pose) {
                vel = p->t_vel;
                h = p->t_h;
            }
            pk_track_pose(p->track, vals, has, vals[0], vals[1], vals[2], p->t_x0, lift,
                          ground, extra, vel, h);
            p->t_pose = 0;
        }
        int stepping = -1;
        double sx = 0.0, sy = 0.0;
        if (p->st_on && p->rx_done < 0) {  /* Tracker._stepped (the step ends with the
                                            reaction: _weight) */
            double u = (double)(s - p->st_start) * p->rx_dt / p->st_time;
            u = u < 1.0 ? u : 1.0;  /* min(1.0, u) */
            double x = p->st_x0 + (p->st_x1 - p->st_x0) * u;
            double y = p->st_y0 + (p->st_y1 - p->st_y0) * u
                       + p->st_lift * sin(3.14159265358979323846264338327950288 * u);
            double back = weight <= p->st_low ? 0.0 : (weight - p->st_low) / (1.0 - p->st_low);
            stepping = p->st_row;
            const double *tg = p->track->targets + 3 * stepping;
            sx = x + (tg[0] - x) * back;
            sy = y + (tg[1] - y) * back;
        }
        pk_track_pull(p->track, weight, p->t_rows, stepping, sx, sy, p->g_on, no_lift,
                      p->g_rise, p->t_period);
        p->t_ticks++;
        p->t_last = s;
    }
control:
    if (s % p->every) {  /* an arrival, or an entry's start (its _write): all written */
        if (p->states && (p->states->started == s || pk_arriving(p, s)))
            pk_blend_write(p, s);
        return 0;
    }
    p->writes++;
    if (p->states)  /* (arrivals too, logged) */
        pk_blend_write(p, s);
    else for (int j = 0; j < p->n_blend; j++) {  /* BlendController._write, none arrived */
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
    if (p->states && p->states->fb_on) {  /* (the rows the state's: kernel_poll_feed) */
        pk_feed_tick(p, p->states, s, &com);
    } else if (p->feedback) {  /* Feedback.tick: pk_feedback_tick, the centre of mass
                                  shared */
        pk_feedback_add(p->feedback, com.v, &com.done);
        p->fb_ticks++;
    }
    return 0;
}

/* The input events due at ``s`` (a mouse move, a stick), their maps as the runtime's
   plain maps write them (maps._plain_run: one joint, clamped, linear), then its pose
   grids (maps._grid_run's, on a mouse move's x and y): 1 when one is
   not this call's to apply (Python applies it, and what comes after it) */
static int pk_events(pk_poll_plan *p, int s)
{
    while (p->ev_done < p->n_ev && p->ev_step[p->ev_done] == s) {
        int e = p->ev_done, kind = p->ev_kind[e];
        if (kind == PK_EV_SAMPLE) {  /* a performer's sample (runtime._on_channels) */
            if (!p->ch_n || pk_sample(p, e, s))
                return 1;
            p->ev_done++;
            continue;
        }
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
        if (p->k_grid && p->k_grid[kind])  /* a cat's legs' grids (maps._grid_run) */
            pk_grid_run(p->k_grid[kind], p->ev_v[2 * e], p->ev_v[2 * e + 1]);
        p->ev_done++;
    }
    return 0;
}

/* Session.advance's frame check at a frame's end: the root in the world box, not
   flying off (1: passed, or not a frame's end) */
static int pk_frame_ok(pk_poll_plan *p, int s)
{
    if (s % p->frame_every == 0) {
        pk_vect q = get_position(p->root), v;
        if (!(p->x0 < q.x && q.x < p->x1 && p->y0 < q.y && q.y < p->y1))
            return 0;
        v = get_velocity(p->root);
        if (!(v.x * v.x + v.y * v.y < p->max_speed2))
            return 0;
    }
    return 1;
}

/* ``tick_first``: the tick at ``now`` too (else Python's tick has run there) */
int pk_poll(void *space, double dt, int now, int stop, pk_poll_plan *p, int tick_first)
{
    int s = now;
    p->fb_ticks = p->writes = p->ev_done = p->t_ticks = 0;
    p->rx_done = p->t_last = -1;
    if (p->states)
        p->states->n_log = p->states->n_val = 0;
    if (tick_first && pk_tick(p, s))
        return s;
    for (;;) {
        space_step(space, dt);
        s++;
        if (s >= stop) {
            if (p->ev_at_stop && p->n_ev && s == stop && pk_frame_ok(p, s))
                pk_events(p, s);  /* (a refused one: Python's, as ever) */
            return s;
        }
        if (!pk_frame_ok(p, s))  /* Session.advance's frame check */
            return s;
        if (p->n_ev && pk_events(p, s))  /* (the events at ``s`` come before its tick) */
            return s;
        if (pk_tick(p, s))
            return s;
    }
}
"""
