"""The C of ``Simulation.blown_up``, the history's health check (every 0.5 s of a run,
on every log): NaN or a runaway velocity anywhere. In Python it reads each link
through four of pymunk's C calls and six ``math.isfinite`` (about 12 us a check on the
biped, 60 a walker's replay, cold after thousands of compiled steps); here one call.
The same tests in the same terms (``isfinite``; ``vx * vx + vy * vy`` against
``MAX_SPEED ** 2`` and ``|w|`` against ``50 * MAX_SPEED``, both worked out in Python and
handed over), so the answer is the same; the first link that fails answers.
"""

HEALTH_CDEF = """
int pk_blown_up(void **bodies, int n, double max_speed2, double max_spin);
"""

HEALTH_SOURCE = r"""
int pk_blown_up(void **bodies, int n, double max_speed2, double max_spin)
{
    for (int i = 0; i < n; i++) {
        pk_vect v = get_velocity(bodies[i]), p = get_position(bodies[i]);
        double w = get_spin(bodies[i]);
        if (!(isfinite(v.x) && isfinite(v.y) && isfinite(w) && isfinite(p.x)
              && isfinite(p.y) && isfinite(get_angle(bodies[i]))))
            return 1;
        if (v.x * v.x + v.y * v.y > max_speed2 || fabs(w) > max_spin)
            return 1;
    }
    return 0;
}
"""
