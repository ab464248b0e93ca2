"""never_touched: a hurdle run that stood on a hurdle fails its checks (issue 31: it
passed every check it had). Luxo stands 1 s on a hurdle (a static prop under its
start) in a scene of two hurdles on a named track; the log is replayed with its
sidecar, as ``puppet replay --check`` does, so the replay records what each link
touched only because an entry reads it."""

from __future__ import annotations

import math

import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.session import Session
from puppet.testing import replay_log
from puppet.timeline.log import record_events

SCENE = """\
name: hurdles
description: A track with two hurdles, the first right under the start.
ground:
  - name: track
    points: [[-10.0, 0.0], [20.0, 0.0]]
start: {x: 0.0, y: 0.27}
props:
  hurdle_1:
    position: [0.0, 0.25]
    shapes: [{segment: [[-0.3, 0.0], [0.3, 0.0]], radius: 0.02}]
  hurdle_2:
    position: [3.0, 0.25]
    shapes: [{segment: [[-0.3, 0.0], [0.3, 0.0]], radius: 0.02}]
"""


@pytest.fixture(scope="module")
def on_the_hurdle(tmp_path_factory):
    """A 1 s log of Luxo standing on hurdle_1 (no input), a checkpoint every 0.5 s
    (the sample at one reads the restored contacts, not the arbiters)."""
    folder = tmp_path_factory.mktemp("hurdles")
    scene = folder / "hurdles.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    session = Session(load_setup("luxo-mouse", str(scene)), checkpoint_interval=0.5)
    return record_events(session, [], round(1.0 / session.sim.dt), folder / "stood.jsonl")


def _run(log, expect):
    return replay_log(log, expect=expect).outcomes


def test_a_run_that_stood_on_a_hurdle_fails_never_touched(on_the_hurdle):
    hurdles, = _run(on_the_hurdle, [{"never_touched": {"props": ["hurdle_1", "hurdle_2"]}}])
    assert not hurdles.passed and hurdles.kind == "never_touched"
    # (placed 2 mm above it, as every start is, it lands on it at once)
    assert str(hurdles).startswith("FAIL never_touched prop hurdle_1, hurdle_2 with any link "
                                   "from 0 s to the end: base touched prop hurdle_1 at "
                                   "t = 0.03 s (x = 0.08, y = 0.27 m)"), str(hurdles)
    # it stood there the whole second: the margin is the time on it, outside the bound
    assert hurdles.unit == "s" and -1.0 < hurdles.margin < -0.95


def test_what_it_did_not_touch_passes(on_the_hurdle):
    other, track, lamp, later = _run(on_the_hurdle, [
        {"never_touched": {"props": ["hurdle_2"]}},
        {"never_touched": {"ground": ["track"]}},          # on the hurdle, off the track
        {"never_touched": {"links": ["upper_arm"], "props": ["hurdle_1"]}},
        {"never_touched": {"props": ["hurdle_1"], "from": 2.0}}])
    assert other.passed and track.passed and lamp.passed, [str(other), str(track), str(lamp)]
    assert other.margin == 0.0
    assert not later.passed and "no samples in the window" in later.measured
    assert later.margin == -math.inf


def test_a_box_and_a_window(on_the_hurdle):
    high, low, window = _run(on_the_hurdle, [
        {"never_touched": {"x_min": -0.5, "x_max": 0.5, "y_min": 0.2}},  # on top of it
        {"never_touched": {"y_max": 0.1}},                              # the floor
        {"never_touched": {"links": ["base"], "props": ["hurdle_1"], "from": 0.5,
                           "until": 0.75}}])
    assert not high.passed and "in x -0.5..0.5 m, y >= 0.2 m" in high.expectation
    assert low.passed, str(low)
    assert not window.passed and "at t = 0.50 s" in window.measured
    assert -0.3 < window.margin < -0.2


def test_names_the_scene_does_not_have_are_refused_at_the_entry(on_the_hurdle, tmp_path):
    with pytest.raises(DataError, match="unknown prop 'hurdle_3'; the scene has: "
                                        "hurdle_1, hurdle_2"):
        _run(on_the_hurdle, [{"never_touched": {"props": ["hurdle_3"]}}])
    side = on_the_hurdle.with_name("stood.expect.yaml")
    side.write_text("expect:\n  - never_touched: {ground: [grass]}\n", encoding="utf-8")
    try:
        with pytest.raises(DataError) as info:  # puppet check, before any replay
            check_file(on_the_hurdle)
        assert str(info.value).startswith(f"{side}:2:")
        assert "unknown ground 'grass'; the scene has: track" in str(info.value)
    finally:
        side.unlink()
    with pytest.raises(DataError, match="give what must not be touched"):
        _run(on_the_hurdle, [{"never_touched": {"links": ["base"]}}])


def test_only_a_run_with_never_touched_records_the_touches(on_the_hurdle):
    plain = replay_log(on_the_hurdle, expect=[{"never_fell": True}])
    assert plain.trajectory.touches is None
    touched = replay_log(on_the_hurdle, expect=[{"never_touched": {"y_max": 0.1}}])
    traj = touched.trajectory
    # a sample has touches exactly where a link is in contact, and only the hurdle's
    for contact, touches in zip(traj.contact, traj.touches):
        assert {k for k, *_ in touches} == set(contact.nonzero()[0].tolist())
        assert {(what, name) for _, what, name, *_ in touches} <= {("prop", "hurdle_1")}
    assert traj.contact.any(axis=1).mean() > 0.95
    assert plain.final_hash == touched.final_hash
