"""The IK solvers on their own: the two-link solution keeps the bend it is told to
prefer; the damped least-squares solver answers within the joint limits."""

from __future__ import annotations

import math

import pytest

from puppet.interface.ik import forward, solve_two_link


def test_two_link_ik_keeps_the_bend_it_is_told_to_prefer():
    a1, a2 = (0.0, 0.2), (0.0, 0.2)
    for d in ((0.15, 0.25), (-0.1, 0.3), (0.25, 0.05)):
        for prefer in (1.0, -1.0, 0.3, -0.3):
            q = solve_two_link(a1, a2, d, prefer)
            assert math.copysign(1, q[1]) == math.copysign(1, prefer), (d, prefer, q)
            assert forward([a1, a2], q)[1] == pytest.approx(d, abs=1e-9)


def test_the_ik_solver_answers_within_the_limits_even_from_a_start_outside_them():
    from puppet.interface.ik import forward, solve_dls

    links = [(0.0, 0.2), (0.0, 0.15), (0.0, 0.1)]
    limits = [(-1.0, 1.0), (-0.5, 0.5), None]
    start = [1.6, -0.9, 0.3]  # the first two past their limits
    _, end = forward(links, start)
    q = solve_dls(links, end, start, limits)  # a target the start already reaches
    assert -1.0 <= q[0] <= 1.0 and -0.5 <= q[1] <= 0.5
