"""interfaces/cat-gap.yaml: cat-bound's keys with the stride run by its phases (read
from the paws), one key a stride, kept until the cat is gathered; space, the leap.
The shipped log over the gap is checked by test_logs.py and tests/test_cat.py."""

import math

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session


def _state(s: Session) -> str:
    return s.runtime.state


def _tap(s: Session, key: str) -> None:
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


def _run(s: Session, strides: int, key_at=None) -> list[tuple[float, float]]:
    """Bound ``strides`` strides on flat ground, ctrl+a tapped as each stride lands
    (``key_at(n)`` may name another key for stride n); returns each flight's back paw
    x at take-off and at the landing."""
    c, dt = s.character, s.sim.dt
    paw = lambda: c.bodies["shin_near"].position.x  # noqa: E731
    flights, n, was, took = [], 0, _state(s), None
    s.advance(round(0.3 / dt))
    _tap(s, "ctrl+a")
    while n < strides and s.time < 20:
        s.advance(1)
        now = _state(s)
        if now != was:
            if now in ("flight", "soaring"):
                took = paw()
            if now == "landed":
                flights.append((took, paw()))
                n += 1
                _tap(s, (key_at(n) if key_at else None) or "ctrl+a")
            was = now
    return flights


def test_the_stride_runs_itself_on_one_key_a_stride():
    """ctrl+a tapped as the cat lands, nothing else: the phases put on the stride's
    poses (in the air the back legs fold, the front legs reach; down, the front legs
    push; then they fold for the next push) and the cat bounds on, upright."""
    s = Session(load_setup("cat-gap", "cat-flat"))
    seen, poses = set(), s.setup.interface.poses
    c = s.character
    start = c.com()[0]
    flights = _run(s, 8)
    assert len(flights) == 8
    assert c.com()[0] - start > 1.2                       # about 0.2 m a stride
    assert c.upright(30)
    for _ in range(round(0.4 / s.sim.dt)):                # one more stride, watched
        s.advance(1)
        seen.add(_state(s))
        if _state(s) == "flight":
            target = math.degrees(c.servos["hip_near"].target)
            assert abs(target - poses["swing"].joints["hip_near"]) < 1e-6
    assert {"pushing", "flight", "landed", "planted", "gathered"} <= seen


def test_a_push_pressed_as_the_cat_lands_waits_for_the_gather():
    """A ctrl+a made in 'landed' is kept (buffer:) through 'planted' and 'gathered' and
    goes the step 'ready' begins: the rhythm is the cat's, not the hand's."""
    s = Session(load_setup("cat-gap", "cat-flat"))
    s.advance(round(0.3 / s.sim.dt))
    _tap(s, "ctrl+a")
    while _state(s) != "landed":
        s.advance(1)
        assert s.time < 1.5
    _tap(s, "ctrl+a")
    states = []
    while _state(s) != "pushing":
        s.advance(1)
        states.append(_state(s))
        assert s.time < 2.5
    assert "planted" in states and "gathered" in states


def test_the_leap_carries_the_back_paws_further_than_a_push():
    """space (the leap) on the stride after the fourth: its back paws come down more
    than three times as far on as a pushed stride's (about 1 m against 0.2 m; over
    cat-gap's gap the paws must go 0.55 m at least), and the cat bounds on."""
    pushed = _run(Session(load_setup("cat-gap", "cat-flat")), 7)
    s = Session(load_setup("cat-gap", "cat-flat"))
    leapt = _run(s, 7, key_at=lambda n: "space" if n == 4 else None)
    push = pushed[4][1] - pushed[4][0]
    leap = leapt[4][1] - leapt[4][0]
    assert leap > 0.7 and leap > 3 * push, (leap, push)
    assert len(leapt) == 7 and s.character.upright(35)


def test_both_keys_from_rest_land_whenever_they_are_pressed():
    """The single-key moves from rest (issue 28): ctrl+a and space pressed at ten steps
    while the cat stands still. From a stand the leap is a push (the 'still' phase: it
    needs the run), so both throw the back paws up and the cat lands on its paws,
    upright, the body never down, ready again: at least 9 of 10 each (all 10 do)."""
    for key in ("ctrl+a", "space"):
        landed = []
        for k in range(10):
            s = Session(load_setup("cat-gap", "cat-flat"))
            c, dt = s.character, s.sim.dt
            s.advance(round(0.8 / dt) + 29 * k)       # settled and still: 0.8 to 1.4 s
            assert _state(s) == "still"
            _tap(s, key)
            air, tilt, body_down = 0.0, 0.0, False
            for _ in range(round(1.2 / dt)):
                s.advance(1)
                if not (c.in_contact("shin_near") or c.in_contact("shin_far")):
                    air += dt
                tilt = max(tilt, abs(math.degrees(c.root_angle())))
                body_down |= any(c.in_contact(n) for n in ("hips", "chest", "head"))
            landed.append(air >= 0.05 and tilt < 45 and not body_down and c.upright(25)
                          and _state(s) in ("ready", "still"))
        assert sum(landed) >= 9, (key, landed)
