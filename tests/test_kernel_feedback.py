"""Feedback's compiled call (controllers/feedback_kernel.py, ``pk_feedback_tick``) and
its Python path give the same bits: every sensor kind it reads, the add maps' sums
and writes, what Feedback keeps (base and last, in their dicts' order) through state
changes and checkpoints, and the walkers' replays. None reads a clock."""

from __future__ import annotations

import pytest
from kernel_paths import needs_cc

from puppet.interface.conditions import map_reader
from puppet.physics.snapshot import restored_touching
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

# every kind the kernel reads, and those it is handed (the lean, a servo's torque)
SENSORS = ["com.x", "com.y", "com.vx", "com.vy", "com.dx.foot_near", "angle.thigh_far",
           "spin.pelvis", "joint.knee_near", "height.foot_far", "lead.foot_far.foot_near",
           "root.angle", "com.dx.support", "com.fall_time", "com.spin", "lean",
           "torque.hip_far"]


def _session(name: str):
    log = read_log(f"assets/logs/{name}.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    return session, LogFeeder(session, log), log


@needs_cc
def test_every_sensor_kind_reads_what_the_python_readers_read(path_of):
    """A plan of one add map per sensor: the values the kernel stores in the inputs are
    map_reader's to the bit, and the targets it writes are the Python path's, on a
    back flip's run-up, flight and landing, and right after a checkpoint (the support
    polygon of the snapshot's contacts, read in Python)."""
    from puppet.data.interfaces import LinearMapSpec
    from puppet.interface import maps
    from puppet.interface.controllers.feedback import Feedback
    from puppet.interface.ownership import JointOwners

    assert path_of("c") is not None
    session, feeder, _ = _session("biped-backflip")
    character = session.character
    specs = [LinearMapSpec(input=f"sensor.{s}", joints={"neck": 0.7, "waist": -1.3},
                           from_=(-1.0, 2.0), to=(-5.0, 7.0),
                           clamp=i % 2 == 0, combine="add") for i, s in enumerate(SENSORS)]
    specs.append(LinearMapSpec(joints={"neck": 0.7, "elbow_far": 2.0}, add=3.0,
                               combine="add"))
    adders = [maps.compile_contribution(m) for m in specs]
    readers = [(f"sensor.{s}", map_reader(s, character)) for s in SENSORS]
    servos = character.servos
    done = 0
    restored = 0
    for step in (600, 1500, 2100, 2700, 3000, 3300):
        feeder.advance(step - done)
        done = step
        if step in (600, 3000):  # the support polygon: the snapshot's contacts
            session.perform("checkpoint")
            restored += restored_touching(session.sim.space) is not None
        got = []
        before = {j: s.target for j, s in servos.items()}
        for how in ("c", "python"):
            path_of(how)
            inputs: dict = {}
            feedback = Feedback(servos, JointOwners(), inputs, 1, character.sample, character)
            feedback.set_maps(readers, (), adders)
            assert (feedback._plan is not None) == (how == "c")
            feedback.tick(step)
            got.append([dict(inputs), {j: s.target for j, s in servos.items()},
                        feedback.get_state()])
            servos["waist"].target += 0.25  # written by another: its base is read again
            feedback.set_maps(readers, (), adders[5:9])  # the others go inactive
            feedback.tick(step + 1)
            assert (feedback._plan is not None) == (how == "c")
            got[-1] += [{j: s.target for j, s in servos.items()}, feedback.get_state()]
            for j, s in servos.items():
                s.target = before[j]
        assert repr(got[0]) == repr(got[1]), step
        assert got[0][0] == {n: r() for n, r in readers}  # (each read after the tick)
    assert restored == 2


def _states(name: str, at: list[int]) -> list:
    session, feeder, log = _session(name)
    out, done = [], 0
    for step in at:
        feeder.advance(step - done)
        done = step
        runtime = session.runtime
        out.append((runtime.feedback.get_state(), runtime.get_state()["controllers"],
                    [s.target for s in session.character.servos.values()]))
    feeder.advance(log.last_step - done)
    return out + [session.sim.state_hash() == log.end_hash]


@needs_cc
@pytest.mark.parametrize("name", ["biped-auto-walk", "biped-backflip",
                                  "biped-handstand"])
def test_feedback_keeps_the_same_state_on_both_paths(name, path_of):
    """What a checkpoint keeps of feedback (each joint's base and last, in order), every
    target, and the end hash, are the same on both paths through the walk's and the
    flip's state changes, and the handstand's support polygon read in Python."""
    at = [700, 1333, 2222, 3001, 3500]
    assert path_of("c") is not None
    with_kernel = _states(name, at)
    assert path_of("python") is None
    assert repr(_states(name, at)) == repr(with_kernel)
    assert with_kernel[-1] is True
    assert any(state[0][1] for state in with_kernel[:-1])  # something was added to
