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
