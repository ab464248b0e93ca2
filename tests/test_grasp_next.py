"""A grasp that skips the place its chain last let go of (``skip_released``): one key
lets go and arms for the next rung, whenever the limb passes it - the gymnast's `v`
(both hands) and `f` (both feet) on the ladder. The place let go of is part of the
runtime's state: checkpoints, rewinds, resets and replays keep it exactly."""

from __future__ import annotations

import pymunk
import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.physics.props import Prop
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.log import read_log, record_events
from puppet.timeline.replay import replay

# the start of the bound climb: hands open, to rung 5 (1.5 m), gripped; bound mapping
START = [(0, ev.key("q", True)), (1, ev.key("q", False)), (1, ev.key("w", True)),
         (2, ev.key("w", False)), (2, ev.key("d", True)), (3, ev.key("d", False)),
         (96, ev.key("z", True)), (97, ev.key("z", False)), (97, ev.key("x", True)),
         (98, ev.key("x", False)), (576, ev.key("2", True)), (577, ev.key("2", False)),
         (577, ev.mouse(0.5, 0.0))]


def climber() -> Session:
    return Session(load_setup("biped-gymnast", "ladder"))


def rung(s, chain):
    """The rung a chain holds (its height, rounded to cm), or None."""
    p = s.sim.grasp_point(chain)
    return None if p is None else round(p[1], 2)


def test_a_plain_regrasp_catches_the_rung_it_left_the_skipping_one_does_not():
    s = climber()
    play(s, START, 960)
    assert rung(s, "hand_near") == rung(s, "hand_far") == 1.5
    for key in ("z", "z"):  # let go and grip again: the hand is still there
        s.handle(ev.key(key, True))
        s.handle(ev.key(key, False))
    s.advance(2)
    assert rung(s, "hand_near") == 1.5

    s = climber()
    play(s, START, 960)
    s.handle(ev.key("v", True))
    s.handle(ev.key("v", False))
    assert s.runtime.machines["near_hand"].current == "climbing"
    assert s.runtime.machines["far_hand"].current == "climbing"  # one key, both hands
    held = s.runtime.grasping.released
    assert set(held) == {"hand_near", "hand_far"}
    assert held["hand_near"][0] == "ladder" and held["hand_near"][1] == pytest.approx((0, 1.5))
    s.advance(240)  # half a second within reach of rung 5: not caught again
    assert rung(s, "hand_near") is None and rung(s, "hand_far") is None
    assert set(s.runtime.grasping.armed) == {"hand_near", "hand_far"}  # still armed


def test_the_skipping_grasp_takes_the_next_rung_the_stroke_brings_it_to():
    s = climber()
    play(s, START, 960)
    s.handle(ev.key("f", True))  # both feet from the floor: any rung (nothing let go of)
    s.handle(ev.key("f", False))
    play(s, [(s.steps, ev.mouse(0.8, 1.0))], s.steps + 720)
    assert rung(s, "foot_near") == rung(s, "foot_far") == 0.3
    s.handle(ev.key("f", True))  # again: not rung 1, the next one the stroke passes
    s.handle(ev.key("f", False))
    assert rung(s, "foot_near") is None
    play(s, [(s.steps, ev.mouse(0.5, 0.0))], s.steps + 960)
    play(s, [(s.steps, ev.mouse(1.0, 0.85))], s.steps + 960)
    assert rung(s, "foot_near") == rung(s, "foot_far") == 0.6


def test_nearest_skips_an_excluded_place_on_points_and_segments():
    body = pymunk.Body(body_type=pymunk.Body.STATIC)
    prop = Prop("p", body, {"a": (0.0, 0.0), "b": (0.0, 0.3)}, [((1.0, 0.0), (1.0, 1.0))], [])
    assert prop.nearest((0.0, 0.01))[2] == "a"
    assert prop.nearest((0.0, 0.01), (0.0, 0.0, 0.05))[2] == "b"
    d, p, name = prop.nearest((1.0, 0.5), (1.0, 0.5, 0.1))  # on the bar: the nearest
    assert name is None and p == pytest.approx((1.0, 0.4))   # place outside the circle
    assert d == pytest.approx(0.1)
    d, p, _ = prop.nearest((1.0, 0.98), (1.0, 1.0, 0.1))    # the circle covers the end
    assert p == pytest.approx((0.0, 0.3)) or p == pytest.approx((1.0, 0.9))
    assert d == pytest.approx(0.08)


EVENTS = START + [(1000, ev.key("f", True)), (1001, ev.key("f", False)),
                  (1001, ev.mouse(0.8, 1.0)), (1300, ev.key("c", True)),  # a checkpoint
                  (1301, ev.key("c", False)), (1700, ev.key("v", True)),
                  (1701, ev.key("v", False)), (1701, ev.mouse(1.0, 0.0)),
                  (2000, ev.key("c", True)), (2001, ev.key("c", False))]
END = 3200


def test_where_it_let_go_survives_checkpoints_rewinds_resets_and_replays(tmp_path):
    straight = climber()
    play(straight, EVENTS, END)
    want = straight.sim.state_hash()
    assert set(straight.runtime.grasping.released) == {"hand_near", "hand_far"}

    s = climber()  # back to the checkpoint after the hands let go (rung 5 remembered)
    play(s, EVENTS, 2600)
    s.handle(ev.action("restore"))
    assert s.steps == 2000
    assert set(s.runtime.grasping.released) == {"hand_near", "hand_far"}
    play(s, [e for e in EVENTS if e[0] > s.steps], END)
    assert s.sim.state_hash() == want

    s = climber()  # a rewind between keyframes, then on
    play(s, EVENTS, 2900)
    s.rewind_to(1600)
    assert "hand_near" not in s.runtime.grasping.released  # not let go of yet
    play(s, [e for e in EVENTS if e[0] > s.steps], END)
    assert s.sim.state_hash() == want

    s = climber()  # a reset forgets it
    play(s, EVENTS, 2000)
    s.handle(ev.action("reset"))
    assert s.runtime.grasping.released == {}

    path = record_events(climber(), EVENTS, END, tmp_path / "climb.jsonl")
    assert read_log(path).end_hash == want
    assert replay(path, check=False).final_hash == want
