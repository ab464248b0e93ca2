"""``ik_two.round_clamp`` and C's ``pk_two_link`` on odd joint limits (review2): limits
past +-180 deg, lower above upper, wider than a turn, a half turn exactly, infinite:
the same bits on both paths, and the answer within the limits."""

from __future__ import annotations

import math
import random

from kernel_paths import needs_cc

from puppet.interface.ik_two import TwoLink, round_clamp

R = math.radians
LIMITS = [(R(-60), R(180)), (R(-180), R(60)), (R(0), R(200)), (R(-200), R(0)),
          (R(60), R(-60)), (R(-400), R(400)), (R(170), R(190)), (R(-190), R(-170)),
          (0.0, 0.0), (-math.pi, math.pi), (float("-inf"), float("inf"))]
SECOND = [None, (R(-150), R(-5)), (R(90), R(-90)), (R(0), R(270))]


def _solves() -> list:
    rng, out = random.Random(1), []
    for lim0 in LIMITS:
        for lim1 in SECOND:
            two = TwoLink((0.3, 0.25, 0.1, -0.2), ((0.3, 0.0), (0.25, 0.0)), [lim0, lim1],
                          0.05, 1e-6, 20)
            for _ in range(60):
                out.append(two.solve(rng.uniform(-0.7, 0.7), rng.uniform(-0.7, 0.7),
                                     rng.uniform(-3.0, 3.0)))
    return out


@needs_cc
def test_odd_limits_same_bits_on_both_paths(path_of):
    assert path_of("c") is not None
    c = _solves()
    assert path_of("python") is None
    py = _solves()
    assert [tuple(map(float.hex, q)) for q in c] == [tuple(map(float.hex, q)) for q in py]


def test_round_clamp_edges():
    lo, hi = R(-60), R(180)
    assert round_clamp(R(-179.9), lo, lo, hi) == hi  # nearer round the circle
    assert round_clamp(R(-100), lo, lo, hi) == lo  # nearer on the line
    assert math.isnan(round_clamp(float("nan"), float("nan"), lo, hi))
    # a limit past 180 deg: -170 is 190, within; the nearer limit round is 200 (the
    # DLS from there finds 190)
    assert round_clamp(R(-170), 0.0, 0.0, R(200)) == R(200)
