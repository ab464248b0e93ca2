"""The C of a pose put on by a state the loop enters (``kernel_poll_states``' entries;
``interface.poll_poses`` makes the rows): ``poses.pose_writer``'s writes, in its order
- a target (``cpDampedRotarySpringSetRestAngle``), a stiffness
(``cpDampedRotarySpringSetStiffness``), a torque cap (``cpConstraintSetMaxForce``) -
through the setters' addresses the states table carries (``f_stiffness``,
``f_max_force``: pymunk's own, as ``servo.SET_STIFFNESS`` and ``SET_MAX_FORCE``).
Kept apart so that other kinds of entry grow beside it, not in it.
"""

POSES_SOURCE = r"""
/* a pose's target on a joint a blend row carries: owners.take lets the blend go
   (Python's tick does that); 1 when the entry of ``b`` takes none */
static int pk_pose_fits(pk_poll_plan *p, pk_states *st, int b)
{
    for (int w = st->w0[b]; w < st->w1[b]; w++) {
        if (st->w_what[w] != 0)
            continue;
        for (int j = 0; j < p->n_blend; j++)
            if (st->b_live[j] && p->spring[j] == st->w_spring[w])
                return 0;
    }
    return 1;
}

/* poses.pose_writer for the entry of ``b``: 0 a target, 1 a stiffness, 2 a torque cap */
static void pk_pose_write(pk_states *st, int b)
{
    pk_setd stiffness = (pk_setd)st->f_stiffness, max_force = (pk_setd)st->f_max_force;
    for (int w = st->w0[b]; w < st->w1[b]; w++) {
        int what = st->w_what[w];
        if (what == 0)
            set_rest_angle(st->w_spring[w], st->w_value[w]);
        else if (what == 1)
            stiffness(st->w_spring[w], st->w_value[w]);
        else
            max_force(st->w_spring[w], st->w_value[w]);
    }
}
"""

KEPT_SOURCE = r"""
/* _enter_state of ``b`` at ``s`` with the press kept for it: InputBuffer.due (the
   press within the binding's buffer, else Python's tick: it stays kept there), then
   run_action of its binding - its goto's state entered (logged 3: no link of the
   tick's chain), its stiffnesses and pose written (rows n_state + b); the press spent
   (logged 2). 0 (nothing done) when any of it does not fit: Python's tick (room for
   5 logs: each entry's and the feedback rows each leaves, kernel_poll_feed) */
static int pk_enter_kept(pk_poll_plan *p, pk_states *st, int b, int s)
{
    int g = st->kept_live ? st->k_goto[b] : -1, i = 0;
    if (g < 0)
        return pk_enter(p, st, b, s);
    for (int r = st->t0[g]; r < st->t1[g]; r++)
        i += st->r_ncond[r];
    if (s - st->kept_at > st->k_window[b] || st->t1[g] - st->t0[g] > st->max_trans
            || i > st->max_cond || st->n_log + 5 > st->max_log
            || !pk_pose_fits(p, st, g) || !pk_pose_fits(p, st, st->n_state + b))
        return 0;
    if (!pk_enter(p, st, b, s))
        return 0;
    st->kept_live = 0;
    pk_log(st, s, 2, b);
    pk_enter(p, st, g, s);  /* (fits: checked above; its entry a pose or nothing) */
    st->l_kind[st->n_log - 1] = 3;
    pk_pose_write(st, st->n_state + b);
    return 1;
}
"""

_SETTERS = ("cpDampedRotarySpringSetStiffness", "cpConstraintSetMaxForce")


def setters(kern) -> tuple:
    """(``f_stiffness``, ``f_max_force``): pymunk's setters as the kernel's pointers,
    looked up once per loaded kernel."""
    got = getattr(kern, "_pose_setters", None)
    if got is None:
        from pymunk._chipmunk_cffi import ffi, lib

        got = kern._pose_setters = tuple(kern.pointer(ffi.addressof(lib, name))
                                         for name in _SETTERS)
    return got
