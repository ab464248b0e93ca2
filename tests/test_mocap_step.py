"""KD tracking follows a performer the same on any simulation step (issue 29): a
sample that comes between two control steps acts at once (the tracker's control steps
move to it), and the trajectory expectations read is sampled at 120 Hz on any step,
so a 60 Hz stream on a 1/240 s step is not read at one point of each frame."""

from __future__ import annotations

import math

import pytest

from puppet.data.catalog import load_setup
from puppet.data.playtest import noise_at
from puppet.mocap.bvh import read_bvh
from puppet.mocap.clip_source import ClipSource
from puppet.mocap.retarget import load_mapping, retarget_clip
from puppet.session import Session
from puppet.timeline.other_physics import OtherPhysics
from puppet.timeline.playtest import run_try
from puppet.timeline.replay import replay
from puppet.timeline.trajectory import sample_every


@pytest.fixture(scope="module")
def walk():
    return retarget_clip(read_bvh("assets/mocap/cmu-131_01-walk.bvh"),
                         load_mapping("assets/mappings/cmu-131.yaml"))


def _run(session, events, until_step, each_step=None):
    i = 0
    while session.steps < until_step:
        while i < len(events) and events[i][0] <= session.steps:
            session.handle(events[i][1])
            i += 1
        session.advance(1)
        if each_step is not None:
            each_step(session)


def _knee_target(session) -> float:
    return session.character.servos["knee_near"].target


def test_a_sample_between_two_control_steps_acts_at_once(walk):
    s = Session(load_setup("biped-mocap"))
    tracker = s.runtime.tracker
    assert tracker.every == 4  # 120 Hz on 1/480 s
    events = [(step + 1, e) for step, e in ClipSource(walk).events(s.sim.dt, 1.0)]
    arrive, event = next((st, e) for st, e in events if st > 240)
    assert arrive % 4 == 1  # three steps before the next control step
    _run(s, events, arrive)
    before = _knee_target(s)
    s.handle(event)
    s.advance(1)
    want = math.radians(event["values"][tracker.joints["knee_near"]])
    assert _knee_target(s) == pytest.approx(want) and before != pytest.approx(want)
    assert tracker.phase == arrive


def _knee_rms(walk, shift: int) -> float:
    """The near knee's RMS from its channel over the clip's walking (4.3-6.7 s), at
    every step, its samples coming ``shift`` steps after the control steps."""
    s = Session(load_setup("biped-mocap"))
    events = [(step + shift, e) for step, e in ClipSource(walk).events(s.sim.dt, 6.7)]
    errors = []

    def read(session):
        if session.steps >= 2064:
            servo = session.character.servos["knee_near"]
            want = math.radians(session.runtime.channels["knee_near"])
            errors.append(math.degrees(servo.angle - want))

    _run(s, events, 3216, read)
    return math.sqrt(sum(e * e for e in errors) / len(errors))


def test_how_well_the_figure_follows_does_not_hang_on_when_the_samples_come(walk):
    # at c8ab954: 8.35 deg aligned, 10.16 three steps before a control step
    aligned, late = _knee_rms(walk, 0), _knee_rms(walk, 1)
    assert aligned < 8.6 and abs(late - aligned) < 0.1


def test_the_trajectory_is_sampled_at_120_hz_on_any_step():
    assert sample_every(1 / 480) == 4 and sample_every(1 / 240) == 2
    assert sample_every(1 / 120) == 1 and sample_every(1 / 60) == 1
    result = replay("assets/logs/biped-mocap-walk.jsonl", physics=OtherPhysics(dt=1 / 240))
    gaps = set((result.trajectory.step[1:-1] - result.trajectory.step[:-2]).tolist())
    assert gaps == {2}


@pytest.mark.parametrize("index", [1, 5])  # (their stream lands 3 steps late on 1/240 s)
def test_the_mocap_walk_passes_on_a_1_240_s_step_whenever_its_frames_come(index):
    # on main at c8ab954 these tries followed the knee 11.9 deg RMS (10.4 followed
    # at 1/480 s): their frames all came just before a trajectory sample
    result = run_try("biped-mocap-walk", noise_at("human"), 0, index,
                     OtherPhysics(dt=1 / 240))
    assert result.passed, result.failed


def test_a_checkpoint_keeps_where_the_control_steps_are(walk):
    s = Session(load_setup("biped-mocap"))
    events = [(step + 3, e) for step, e in ClipSource(walk).events(s.sim.dt, 2.0)]
    _run(s, events, 482)
    s.checkpoint()
    rest = [e for e in events if e[0] >= 482]
    _run(s, rest, 900)
    first = s.sim.state_hash()
    s.restore_checkpoint()
    assert s.runtime.tracker.phase % 4 == 3
    _run(s, rest, 900)
    assert s.sim.state_hash() == first
