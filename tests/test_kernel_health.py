"""``Simulation.blown_up`` in the kernel (``physics.kernel_health``) answers as the
Python loop does: a NaN or an infinity in any link's place, angle, velocity or spin,
a speed or a spin just past, at and just under its limit, on the biped and on Luxo,
and after a re-seat on a fresh space (new bodies)."""

from __future__ import annotations

import math

import pytest
from kernel_paths import needs_cc

from puppet.data.catalog import load_setup
from puppet.physics import reseat
from puppet.physics import simulation as _sim
from puppet.physics.simulation import MAX_SPEED
from puppet.session import Session

NAN, INF = float("nan"), float("inf")
LIMIT = MAX_SPEED / math.sqrt(2.0)  # (vx = vy: the sum of squares at the limit's square)
CASES = [("velocity", (NAN, 0.0)), ("velocity", (0.0, INF)), ("velocity", (-INF, 0.0)),
         ("position", (NAN, 1.0)), ("position", (1.0, INF)), ("angle", NAN),
         ("angle", -INF), ("angular_velocity", NAN), ("angular_velocity", INF),
         ("velocity", (MAX_SPEED, 0.0)), ("velocity", (math.nextafter(MAX_SPEED, INF), 0.0)),
         ("velocity", (math.nextafter(MAX_SPEED, 0.0), 0.0)), ("velocity", (LIMIT, LIMIT)),
         ("velocity", (math.nextafter(LIMIT, INF), LIMIT)),
         ("angular_velocity", 50 * MAX_SPEED),
         ("angular_velocity", -math.nextafter(50 * MAX_SPEED, INF)),
         ("angular_velocity", math.nextafter(50 * MAX_SPEED, 0.0)), ("velocity", (3.0, -2.0))]


def _both(sim, monkeypatch) -> tuple[bool, bool]:
    in_c = sim.blown_up()
    with monkeypatch.context() as m:
        m.setattr(_sim._kernel, "get", lambda: None)
        in_python = sim.blown_up()
    return in_c, in_python


@needs_cc
@pytest.mark.parametrize("iface", ["biped-walk", "luxo-keys"])
def test_the_kernel_finds_what_python_finds(iface, path_of, monkeypatch):
    assert path_of("c") is not None
    session = Session(load_setup(iface))
    session.advance(40)
    sim = session.sim
    assert _both(sim, monkeypatch) == (False, False)
    answers = []
    for link in list(sim.character.bodies)[:: max(1, len(sim.character.bodies) // 3)]:
        for what, value in CASES:
            body = sim.character.bodies[link]
            kept = getattr(body, what)
            setattr(body, what, value)
            got = _both(sim, monkeypatch)
            assert got[0] == got[1], (link, what, value, got)
            answers.append(got[0])
            setattr(body, what, kept)
    assert True in answers and False in answers
    with monkeypatch.context() as m:  # a re-seat on a fresh space: the new bodies read
        m.setattr(reseat, "live_objects", lambda *a: None)
        sim._rebuild(sim._state())
    body = next(iter(sim.character.bodies.values()))
    body.velocity = (NAN, 0.0)
    assert _both(sim, monkeypatch) == (True, True)
