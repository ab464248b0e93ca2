"""The C of intentional contacts at a tracker's control step, for ``pk_poll``'s tick
(``kernel_poll``): ``IntentionalContacts._contacts`` (interface/controllers/
tracking_contact.py) operation for operation, on the rows ``interface/poll_track.py``
fills - each held hand of ``tracking.contacts`` in its order, its grasp's pin (the
body it holds and the point on it), the contact's start and the performer's vector
and rates as Python worked them out at the sample. ``math.hypot`` is ``pk_hypot``
(CPython's, ported), ``math.atan2`` and ``math.remainder`` C's (the same answers on
finite values: CPython's special cases are C99's)."""

CONTACT_SOURCE = r"""
/* IntentionalContacts._performer_rate of each contact at a tick after a sample the
   run applied (pk_sample: the hands' channels in c_xy): the performer's vector now
   (_performer_vector) and its rates from the vector at the sample before */
static void pk_contact_rates(pk_poll_plan *p)
{
    for (int j = 0; j < p->c_n; j++) {
        if (p->t_sample <= p->c_seen[j])
            continue;
        double *r = p->c_row + 10 * j, x = p->c_xy[2 * j], y = p->c_xy[2 * j + 1];
        double a = atan2(y, x), l = pk_hypot(x, y);
        double h = (double)(p->t_sample - p->c_seen[j]) * p->c_dt;
        r[6] = a;
        r[7] = l;
        r[8] = remainder(a - p->c_sv[2 * j], TURN) / h;
        r[9] = (l - p->c_sv[2 * j + 1]) / h;
        p->c_sv[2 * j] = a;
        p->c_sv[2 * j + 1] = l;
        p->c_seen[j] = p->t_sample;
    }
}

/* IntentionalContacts._contacts: the swing PD and the spring of each held hand, as
   one velocity change of every body; ``com``: the tick's centre of mass memo (worked
   out again here, as Python's reads it fresh, and spent after: the velocities move) */
static void pk_contacts(pk_poll_plan *p, pk_com_now *com)
{
    double v[4];
    pk_contact_rates(p);  /* (Python's: each hand's rate before its force) */
    pk_com(p->com_bodies, p->com_mass, p->com_gx, p->com_gy, p->com_n, p->com_total, v);
    double x = v[0], y = v[1], vx = v[2], vy = v[3];
    double fx = 0.0, fy = 0.0;
    for (int j = 0; j < p->c_n; j++) {
        const double *r = p->c_row + 10 * j;  /* ax, ay, a0, l0, p0, q0, me0, me1, r0, r1 */
        pk_vect local = {r[0], r[1]};
        pk_vect held = to_world(p->c_body[j], local);
        double rx = held.x - x, ry = held.y - y;
        double length = pk_hypot(rx, ry);
        if (length < 1e-6)
            continue;
        double angle = atan2(ry, rx);
        double ux = -ry / length, uy = rx / length;
        double turn = (-vx * ux - vy * uy) / length;
        double want = r[2] + remainder(r[6] - r[4], TURN);
        double torque = p->c_swing * remainder(want - angle, TURN)
                        + p->c_swing_d * (r[8] - turn);
        double grow = (-vx * rx - vy * ry) / length;
        double pull = p->c_spring * (r[3] + r[7] - r[5] - length)
                      + p->c_damp * (r[9] - grow);
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

/* c_late: the velocities as they were (at most PK_LATE bodies: poll_track), then the
   contacts; undone when the tick is Python's after all (the same bits back) */
#define PK_LATE 64
static void pk_contacts_first(pk_poll_plan *p, pk_com_now *com, pk_vect *was)
{
    for (int i = 0; i < p->com_n; i++)
        was[i] = get_velocity(p->com_bodies[i]);
    pk_contacts(p, com);
}

static void pk_contacts_undo(pk_poll_plan *p, const pk_vect *was)
{
    for (int i = 0; i < p->com_n; i++)
        set_velocity(p->com_bodies[i], was[i]);
}
"""
