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


def _reference_two(chain, d, prefer):
    """The general solvers' answer for a two-joint chain (what Chain.solve did)."""
    from puppet.interface.ik import _clamp, _two_link, solve_dls
    from puppet.interface.ik_two import round_clamp

    q = _two_link(*chain._closed, d, prefer)
    clamped = tuple(_clamp(v, lim) for v, lim in zip(q, chain.limits))
    if clamped == q:
        return q
    clamped = tuple(c if lim is None or c == v else round_clamp(v, c, *lim)
                    for v, c, lim in zip(q, clamped, chain.limits))
    return tuple(solve_dls(list(chain.links), d, clamped, chain.limits))


def test_the_unrolled_two_joint_solver_gives_the_general_solvers_bits():
    """ik_two.TwoLink is a refactor: every recorded reach replays to the same bits only
    if it answers exactly what _two_link and solve_dls answer, limits in the way or not."""
    import random
    import struct

    from puppet.interface.ik import Chain

    bits = lambda q: [struct.pack("<d", v) for v in q]  # noqa: E731 - -0.0 != 0.0 here
    rng = random.Random(29)
    limit_sets = [(None, None), ((-1.0, 1.2), (0.0, 2.4)), ((-0.3, 0.3), None),
                  (None, (-2.5, -0.1)), ((0.0, 0.0), (-0.2, 0.2)),
                  ((-1.05, math.pi), (0.0, 2.6))]  # the biped's shoulder and elbow
    for limits in limit_sets:
        for _ in range(400):
            links = ((rng.uniform(-0.1, 0.1), rng.uniform(0.1, 0.4)),
                     (rng.uniform(-0.1, 0.1), rng.uniform(0.1, 0.4)))
            chain = Chain("c", ("a", "b"), "p", "e", (0.0, 0.0), links, (0.0, 0.0), limits)
            r = rng.choice([0.3, 0.8, 1.5])
            d = (rng.uniform(-r, r), rng.uniform(-r, r))
            prefer = rng.uniform(-3.0, 3.0)
            assert bits(chain._two.solve(*d, prefer)) == bits(_reference_two(chain, d, prefer))


def test_an_answer_past_a_limit_goes_to_the_limit_nearer_round_the_circle():
    """An arm straight up at its 180 deg limit, its target a hair behind: the answer
    wraps to -179.9 deg, and the clamp keeps it at 180, not at the -60 deg limit on the
    other side of the line (which swung a hanging figure's arm down and round)."""
    from puppet.interface.ik import Chain
    from puppet.interface.ik_two import round_clamp

    lo, hi = math.radians(-60), math.pi
    assert round_clamp(math.radians(-179), lo, lo, hi) == hi
    assert round_clamp(math.radians(-100), lo, lo, hi) == lo  # nearer -60 this side
    assert round_clamp(math.radians(-130), lo, lo, hi) == hi  # nearer 180 round
    links = ((0.0, -0.3), (0.0, -0.35))  # hanging down at 0 deg
    chain = Chain("arm", ("shoulder", "elbow"), "chest", "hand", (0.0, 0.0), links,
                  (0.0, 0.0), ((lo, hi), (0.0, math.radians(150))))
    q = chain._two.solve(-0.03, 0.70, 0.0)  # up, a hair behind, out of reach (+x: ahead)
    assert math.degrees(q[0]) > 170, q
