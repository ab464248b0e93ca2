"""The C of intentional contacts at a tracker's control step, for ``pk_poll``'s tick
(``kernel_poll``): ``IntentionalContacts._contacts`` (interface/controllers/
tracking_contact.py) operation for operation, on the rows ``interface/poll_track.py``
fills - each held hand of ``tracking.contacts`` in its order, its grasp's pin (the
body it holds and the point on it), the contact's start and the performer's vector
and rates as Python worked them out at the sample. ``math.hypot`` is ``pk_hypot``
(CPython's, ported), ``math.atan2`` and ``math.remainder`` C's (the same answers on
finite values: CPython's special cases are C99's)."""

CONTACT_SOURCE = r"""
/* IntentionalContacts._contacts: the swing PD and the spring of each held hand, as
   one velocity change of every body; ``com``: the tick's centre of mass memo (worked
   out again here, as Python's reads it fresh, and spent after: the velocities move) */
static void pk_contacts(pk_poll_plan *p, pk_com_now *com)
{
    double v[4];
    pk_com(p->com_bodies, p->com_mass, p->com_gx, p->com_gy, p->com_n, p->com_total, v);
    double x = v[0], y = v[1], vx = v[2], vy = v[3];
    double fx = 0.0, fy = 0.0;
    for (int j = 0; j < p->c_n; j++) {
        pk_vect local = {p->c_ax[j], p->c_ay[j]};
        pk_vect held = to_world(p->c_body[j], local);
        double rx = held.x - x, ry = held.y - y;
        double length = pk_hypot(rx, ry);
        if (length < 1e-6)
            continue;
        double angle = atan2(ry, rx);
        double ux = -ry / length, uy = rx / length;
        double turn = (-vx * ux - vy * uy) / length;
        double want = p->c_a0[j] + remainder(p->c_me0[j] - p->c_p0[j], TURN);
        double torque = p->c_swing * remainder(want - angle, TURN)
                        + p->c_swing_d * (p->c_r0[j] - turn);
        double grow = (-vx * rx - vy * ry) / length;
        double pull = p->c_spring * (p->c_l0[j] + p->c_me1[j] - p->c_q0[j] - length)
                      + p->c_damp * (p->c_r1[j] - grow);
        fx += -torque / length * ux - pull * rx / length;
        fy += -torque / length * uy - pull * ry / length;
    }
    if (fx == 0.0 && fy == 0.0)
        return;
    double dvx = fx / p->c_mass * p->c_period, dvy = fy / p->c_mass * p->c_period;
    for (int i = 0; i < p->com_n; i++) {
        pk_vect w = get_velocity(p->com_bodies[i]);
        w.x = w.x + dvx;
        w.y = w.y + dvy;
        set_velocity(p->com_bodies[i], w);
    }
    com->done = 0;
}
"""
