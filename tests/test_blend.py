"""A pose or set with `over: SECONDS`: the targets travel there along an eased path at
the control rate (puppet/interface/controllers/blend.py), the same path at any step."""

from __future__ import annotations

import math
import textwrap

import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session

LAYOUT = """
name: t
description: poses reached over time
character: luxo
poses:
  fold: {joints: {knee: 115, ankle: {world: -35}}}
keys:
  - {key: a, pose: fold, over: 0.5}
  - {key: s, set: {knee: 20}, over: 0.25}
  - {key: d, set: {knee: 60}}
"""


def session(tmp_path, text: str = LAYOUT, dt: float | None = None) -> Session:
    path = tmp_path / "t.yaml"
    path.write_text(textwrap.dedent(text))
    setup = load_setup(str(path))
    return Session(setup) if dt is None else Session(setup, dt=dt)


def press(s, key):
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


def knee(s) -> float:
    return math.degrees(s.character.servos["knee"].target)


def test_the_targets_travel_eased_and_end_exactly_at_the_pose(tmp_path):
    s = session(tmp_path)
    start = knee(s)
    press(s, "a")
    owners = s.runtime.owners.table
    assert owners["knee"].kind == "blend" and owners["ankle"].kind == "blend"
    s.advance(121)  # half way (0.25 s; written before the step from 120): the ease's 0.5
    assert knee(s) == pytest.approx(start + 0.5 * (115 - start), abs=1e-9)
    s.advance(60)  # three quarters of the time, further than three quarters of the way
    assert knee(s) > start + 0.75 * (115 - start)
    s.advance(60)
    assert knee(s) == pytest.approx(115)
    # arrived: the plain target is nobody's, the world target is held as a pose's is
    assert "knee" not in owners and owners["ankle"].kind == "frame"
    s.advance(480)
    assert math.degrees(s.character.bodies["lower_arm"].angle) == pytest.approx(-35, abs=1.5)


def test_a_later_write_takes_a_travelling_joint_back_and_the_others_go_on(tmp_path):
    s = session(tmp_path)
    press(s, "a")
    s.advance(100)
    press(s, "d")  # the knee to 60 at once: the travel lets it go
    s.advance(40)
    assert knee(s) == pytest.approx(60)
    assert s.runtime.owners.table["ankle"].kind == "blend"  # still travelling
    press(s, "s")  # a set over time travels from where the knee is
    s.advance(60)
    assert 20 < knee(s) < 60
    s.advance(61)
    assert knee(s) == pytest.approx(20)


def test_the_path_is_the_same_at_any_step_length(tmp_path):
    """The target is a function of time on the control rate's grid: at 1/240 s and
    1/480 s steps the knee's target is the same at the same moments."""
    paths = []
    for dt in (1 / 480, 1 / 240):
        s = session(tmp_path, dt=dt)
        press(s, "a")
        path = []
        for _ in range(8):
            s.advance(round(1 / 15 / dt))  # every 1/15 s: a multiple of the control period
            path.append(knee(s))
        paths.append(path)
    assert paths[0] == pytest.approx(paths[1], abs=1e-9)


def test_a_checkpoint_mid_travel_replays_to_the_same_bits(tmp_path):
    from puppet.session.playback import play

    events = [(10, ev.key("a")), (10, ev.key("a", False)), (100, ev.key("c"))]
    straight = session(tmp_path)
    play(straight, events, 400)
    s = session(tmp_path)
    play(s, events, 200)
    s.handle(ev.action("restore"))
    assert s.steps == 100
    play(s, [], 400)
    assert s.sim.state_hash() == straight.sim.state_hash()
    assert s.runtime.get_state() == straight.runtime.get_state()


def test_over_needs_a_pose_or_a_set(tmp_path):
    path = tmp_path / "t.yaml"
    line = "  - {key: f, adjust: {knee: 5}, over: 0.2}"
    path.write_text(textwrap.dedent(LAYOUT) + line + "\n")
    with pytest.raises(DataError) as info:
        check_file(path)
    said = str(info.value)
    assert said.startswith(f"{path}:11:{line.index('0.2') + 1}: ")
    assert "'over' (s) is how long" in said and "\n" not in said
