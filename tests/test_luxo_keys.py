"""Luxo's 14 key actions (interfaces/luxo-keys.yaml) each do what their names say.

Every key is pressed through ``Session.handle`` as the window sends it (key down,
0.1 s, key up) from a stated start state, and the move is measured from the lamp's
bodies: base x (forward is +x), the base's lowest point (how high it got), the shade's
height, and the base's accumulated rotation (counter-clockwise = backward for a lamp
facing +x). The numbers in the comments are what the tuned sequences measure
(measured with the former tools/tune_luxo_keys.py; searched now by assets/tune/luxo-keys-*.yaml).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache

import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session

EVERY = 4  # steps between samples


@dataclass
class Move:
    dx: float = 0.0  # base x change, m
    rise: float = 0.0  # highest base bottom above the floor, m
    turn: float = 0.0  # accumulated base rotation, deg (+ backward, - forward)
    upright: bool = True  # at the end
    fell: bool = False  # base > 90 deg from upright while touching the floor
    airborne: float = 0.0  # longest stretch with no link on the floor, s
    shade: list[tuple[float, float]] = field(default_factory=list)  # (t since key, m)
    lower_arm_angle: float = 0.0  # deg from vertical at the end
    state: str | None = None  # state machine state at the end

    def shade_at(self, t: float) -> float:
        return min(self.shade, key=lambda s: abs(s[0] - t))[1]


def standing() -> Session:
    return Session(load_setup("luxo-keys"))


def sitting() -> Session:
    session = standing()
    tap(session, "z")
    session.advance(round(2.0 / session.sim.dt))
    return session


def on_back() -> Session:
    session = standing()
    c = session.character
    c.place(0.0, 0.6, math.pi, c.start_joint_angles())  # dropped upside down
    session.advance(round(2.0 / session.sim.dt))
    return session


def tap(session: Session, key: str) -> None:
    session.handle(ev.key(key, True))
    session.advance(round(0.1 / session.sim.dt))
    session.handle(ev.key(key, False))


def press(session: Session, key: str, seconds: float = 3.0) -> Move:
    """Tap ``key`` and watch for ``seconds`` (counted from the key press)."""
    c, dt = session.character, session.sim.dt
    # bodies looked up each time: a checkpoint (every 3 s) re-seats the run on restored
    # copies, and a body held from before it stops moving
    x0, a0, t0 = c.bodies["base"].position.x, c.bodies["base"].angle, session.time
    move, stretch = Move(), 0.0

    def sample() -> None:
        nonlocal stretch
        move.rise = max(move.rise, min(s.cache_bb().bottom for s in c.shapes["base"]))
        move.shade.append((session.time - t0, c.link_position("upper_arm")[1]))
        touching = any(c.in_contact(n) for n in c.link_order)
        move.fell |= touching and not c.upright(90.0)
        stretch = 0.0 if touching else stretch + EVERY * dt
        move.airborne = max(move.airborne, stretch)

    session.handle(ev.key(key, True))
    for i in range(round(seconds / dt) // EVERY):
        if i * EVERY == round(0.1 / dt):
            session.handle(ev.key(key, False))
        session.advance(EVERY)
        sample()
    base = c.bodies["base"]
    move.dx = base.position.x - x0
    move.turn = math.degrees(base.angle - a0)
    move.upright = c.upright()
    move.lower_arm_angle = math.degrees(math.remainder(c.bodies["lower_arm"].angle, math.tau))
    move.state = session.runtime.state
    return move


@cache
def from_standing(key: str) -> Move:
    return press(standing(), key)


def lands_upright(m: Move) -> bool:
    return m.upright and not m.fell


# -- hops ---------------------------------------------------------------------------------
def test_large_hop_travels_farther_than_medium_hop_which_travels_farther_than_small_hop():
    small, medium, large = from_standing("q"), from_standing("w"), from_standing("e")
    assert 0.1 < small.dx < medium.dx < large.dx  # 0.21, 0.41, 1.04 m
    assert large.dx > 0.8
    for hop in (small, medium, large):
        assert lands_upright(hop)
        assert hop.airborne >= 0.1  # a hop, not a shuffle
        assert abs(hop.turn) < 20


def test_small_backward_hop_moves_back_and_lands_upright():
    m = from_standing("a")
    assert -0.3 < m.dx < -0.08  # -0.17 m
    assert m.airborne >= 0.1
    assert lands_upright(m) and abs(m.turn) < 20


def test_high_backward_hop_goes_higher_than_the_small_backward_hop():
    high, small = from_standing("s"), from_standing("a")
    assert high.rise > small.rise + 0.03  # 0.30 vs 0.23 m
    assert high.dx < -0.2  # -0.44 m
    assert lands_upright(high) and abs(high.turn) < 20


# -- somersaults --------------------------------------------------------------------------
def test_back_somersault_lands_upright_after_a_full_backward_turn():
    m = from_standing("d")
    assert 300 < m.turn < 420  # +360 deg: one full turn, counter-clockwise (backward)
    assert m.rise > 0.5  # 0.82 m, landing about 1 m back
    assert m.airborne > 0.5  # 0.71 s: the turn is made in the air
    assert lands_upright(m)


def settled(seconds: float):
    def start() -> Session:
        session = standing()
        session.advance(round(seconds / session.sim.dt))
        return session
    return start


def after(key: str, seconds: float):
    def start() -> Session:
        session = standing()
        tap(session, key)
        session.advance(round(seconds / session.sim.dt))
        return session
    return start


STANDING_POSES = {  # every way of standing the keys leave Luxo in
    "the start pose": standing, "settled 0.5 s": settled(0.5), "settled 2 s": settled(2.0),
    "at the medium height": after("2", 2.0), "at the small height": after("1", 2.0),
    "after a small hop": after("q", 2.4), "after a slow stand": after("v", 3.0),
    "after a forward somersault": after("t", 2.9),
}


@pytest.mark.parametrize("start", list(STANDING_POSES))
def test_forward_somersault_lands_upright_from_any_standing_pose(start):
    session = STANDING_POSES[start]()
    assert session.character.upright(10.0)
    m = press(session, "t")
    assert -420 < m.turn < -300  # -360 deg: one full turn, clockwise (forward)
    assert m.rise > 0.5  # 1.2 m
    assert m.airborne > 0.5  # 0.87 s: the turn is made in the air
    assert lands_upright(m) and m.state == "upright"


# -- jumps --------------------------------------------------------------------------------
def test_big_jump_reaches_higher_than_small_jump():
    big, small = from_standing("j"), from_standing("h")
    assert small.rise >= 0.03  # 0.05 m: it leaves the floor
    assert big.rise > small.rise + 0.04  # 0.10 vs 0.05 m
    for jump in (big, small):
        assert lands_upright(jump) and abs(jump.turn) < 30


def test_small_jump_goes_up_not_along():
    m = from_standing("h")
    assert abs(m.dx) < 0.05 and m.airborne > 0.05


# -- sit and stand ------------------------------------------------------------------------
def test_sit_lowers_the_shade_below_15_cm_and_stays_there():
    m = press(standing(), "z", seconds=5.0)
    assert m.shade_at(0.0) > 0.3
    assert m.shade_at(2.0) < 0.15 and m.shade_at(5.0) < 0.15  # 0.13 m
    assert lands_upright(m) and abs(m.dx) < 0.05 and m.state == "sitting"


def test_sit_upright_keeps_the_lower_arm_vertical_with_the_shade_low():
    m = press(standing(), "x")
    assert abs(m.lower_arm_angle) < 15  # 1 deg
    assert m.shade_at(3.0) < 0.15  # 0.12 m
    assert lands_upright(m)


def test_slow_stand_rises_from_sitting_over_more_than_a_second():
    m = press(sitting(), "v")
    assert m.shade[0][1] < 0.15
    low = next(t for t, y in m.shade if y > 0.17)
    high = next(t for t, y in m.shade if y > 0.37)
    assert high - low > 1.0  # 1.4 s from 17 to 37 cm
    assert lands_upright(m) and m.state == "upright"


@pytest.mark.parametrize("key, height", [("1", 0.368), ("2", 0.387)])
def test_stand_keys_reach_their_heights(key, height):
    m = press(standing(), key, seconds=1.5)
    assert m.shade_at(1.5) == pytest.approx(height, abs=0.01)
    assert lands_upright(m)


def test_stand_at_medium_height_is_taller_than_at_small_height():
    assert from_standing("2").shade_at(2.0) > from_standing("1").shade_at(2.0) + 0.015


# -- state-dependent keys -----------------------------------------------------------------
@pytest.mark.parametrize("key, height", [("1", 0.368), ("2", 0.387)])
def test_from_sitting_the_stand_keys_rise_gently_instead_of_jumping(key, height):
    session = sitting()
    assert session.runtime.state == "sitting"
    m = press(session, key)
    assert m.shade_at(3.0) == pytest.approx(height, abs=0.01)
    assert m.rise < 0.06 and lands_upright(m)  # a stand pose from sitting jumps 0.9 m
    assert m.state == "upright"


def test_from_sitting_a_hop_key_stands_luxo_up_first():
    m = press(sitting(), "e")
    assert lands_upright(m) and m.shade_at(3.0) > 0.35 and abs(m.dx) < 0.15


def on_back_tipped() -> Session:
    """Tipped over backwards from the stand pose (not dropped upside down)."""
    session = standing()
    c = session.character
    c.place(0.0, 0.15, math.radians(120), c.start_joint_angles())
    session.advance(round(2.0 / session.sim.dt))
    return session


@pytest.mark.parametrize("key", ["q", "w", "e", "v", "1", "2"])
@pytest.mark.parametrize("start", [on_back, on_back_tipped])
def test_on_its_back_the_hop_and_stand_keys_roll_luxo_over_onto_its_base(start, key):
    session = start()
    assert session.runtime.state == "on_back"
    assert not session.character.upright(80.0)  # lying: the base stands on its edge
    assert session.runtime.binding(key).sequence == "roll_over"
    m = press(session, key)
    assert m.upright and session.runtime.state == "upright"
    assert session.character.upright(10.0)  # standing on its base, not leaning
    assert -130 < m.turn < -60  # -98 deg: rolled forward over onto its base, no more
