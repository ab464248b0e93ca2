"""Poses put on by states the kernel's loop enters, and presses kept for a later state
(``interface.poll_poses``, ``physics.kernel_poll_poses``): the cat's strides replay
call by call to the same machine states, owners, kept presses, servo targets and bits
with the loop entering them, with Python's ticks on the kernel and on the pure-Python
path; and the cases no shipped log has: a key press at the step the loop enters a
state, a pose on a joint a blend carries, a checkpoint restored and a rewind
mid-stride, a hot reload that changes a pose."""

from __future__ import annotations

from unittest.mock import patch

import pytest
from kernel_paths import agree_without_the_loop, needs_cc, trace, traced_edited

from puppet.data.actions import ActionSpec
from puppet.interface import poll_poses, poll_states
from puppet.timeline import replay as _replay
from puppet.timeline.log import read_log

BOUND, GAP = "assets/logs/cat-bound.jsonl", "assets/logs/cat-gap.jsonl"


def _counted(log, chunk):
    """The log traced with the loop; the states it entered with a pose, and those
    entered while a press was kept."""
    handed, counts = poll_states.States.handed_back, [0, 0]

    def counted(self, rt, machine):
        st = self.st
        for e in range(st.n_log):
            if st.l_kind[e] == 1 and self.poses[st.l_arg[e]]:
                counts[0] += 1
                counts[1] += bool(self.kept)
        return handed(self, rt, machine)

    with patch.object(poll_states.States, "handed_back", counted):
        with_loop = trace(log, True, chunk)[0]
    return with_loop, counts


@needs_cc
@pytest.mark.parametrize("chunk", [None, 37])
@pytest.mark.parametrize("path", [BOUND, GAP])
def test_the_loop_puts_on_the_cats_poses_as_the_ticks_do(path, chunk, path_of):
    assert path_of("c") is not None
    log = read_log(path)
    with_loop, (posed, kept) = _counted(log, chunk)
    assert posed > 60 and kept > 20, (posed, kept)  # (each stride: flight, landed, ...)
    agree_without_the_loop(log, with_loop, chunk, path_of)


@needs_cc
def test_the_bound_leaves_python_a_tick_a_stride(path_of):
    """cat-bound's 122 Python ticks a replay (before) are its 24 strides' kept pushes
    (gathered -> ready takes the press: Python's) and a few more."""
    assert path_of("c") is not None
    from puppet.interface.runtime import InterfaceRuntime

    log = read_log(BOUND)
    session = _replay.new_session(log, _replay.setup_for_log(log)[0])
    tick, ticks = InterfaceRuntime.tick, [0]

    def counted(self, step):
        ticks[0] += 1
        return tick(self, step)

    with patch.object(InterfaceRuntime, "tick", counted):
        _replay.LogFeeder(session, log).advance(log.last_step)
    assert session.sim.state_hash() == log.end_hash
    assert 0 < ticks[0] < 40, ticks


def test_which_entries_put_on_a_pose_in_the_loop():
    only = poll_poses.pose_only
    assert only(ActionSpec(pose="swing"), "keys")
    assert only(ActionSpec(pose="swing", mode="keys"), "keys")
    assert not only(ActionSpec(pose="swing", mode="mouse"), "keys")  # a mode change
    assert not only(ActionSpec(pose="swing", over=0.1), "keys")  # a blend (poll_states')
    assert not only(ActionSpec(pose="swing", stiffness={"knee": 3}), "keys")
    assert not only(ActionSpec(pose="swing", goto="flight"), "keys")
    assert not only(ActionSpec(pose="swing", set={"knee": 3.0}), "keys")
    assert not only(ActionSpec(set={"knee": 3.0}), "keys")


def _session(log):
    return _replay.new_session(log, _replay.setup_for_log(log, as_recorded=True)[0])


def test_a_pose_with_frames_or_damping_is_pythons():
    log = read_log(BOUND)
    text = log.header["interface_text"]
    old = "  back_soft: {joints: {}, stiffness:"
    assert text.count(old) == 1
    log.header["interface_text"] = text.replace(
        old, "  soft_damped: {joints: {}, damping: {knee_near: 0.2}}\n"
        "  held_up: {joints: {hip_near: {world: 10}}}\n" + old)
    rt = _session(log).runtime
    rows = poll_poses.pose_rows(rt, ActionSpec(pose="back_over_push"), rt.mode)
    assert [(j, w) for j, w, _ in rows] == [
        ("hip_near", 0), ("knee_near", 0), ("hip_far", 0), ("knee_far", 0),
        ("hip_near", 2), ("knee_near", 2), ("hip_far", 2), ("knee_far", 2)]
    assert poll_poses.pose_rows(rt, ActionSpec(pose="soft_damped"), rt.mode) is None
    assert poll_poses.pose_rows(rt, ActionSpec(pose="held_up"), rt.mode) is None


def _paths(make, path_of):
    """The log ``make()`` gives traced with the kernel's loop, with Python's ticks on
    the kernel and on the pure-Python path: all three the same, call by call."""
    assert path_of("c") is not None
    with_loop, ticks = traced_edited(make(), True), traced_edited(make(), False)
    assert path_of("python") is None
    assert ticks == traced_edited(make(), True)
    assert len(with_loop) == len(ticks)
    for a, b in zip(with_loop, ticks):
        assert a == b, a[0]
    return with_loop


def _with(log, extra: list):
    pairs = sorted(log.pairs() + extra, key=lambda p: p[0])
    log.pairs = lambda: pairs
    return log


def _entries(path: str) -> list:
    """(step, state) of each state the stride enters, from Python's ticks."""
    from puppet.interface.controllers.state_machine import StateMachine

    enter, out = StateMachine.enter, []

    def noted(self, state, now):
        out.append((now, state))
        return enter(self, state, now)
    with patch.object(StateMachine, "enter", noted):
        traced_edited(read_log(path), False)
    return out


def _key(step: int, key: str, down: bool = True):
    return step, {"type": "key", "key": key, "down": down}


@needs_cc
def test_a_key_press_at_the_step_the_loop_enters_a_state(path_of):
    """A pose key (`k`: the front legs stand) pressed at the very step of a stride's
    entries (one call a step, so an entry falls at each event's step): the event
    first, then the tick's entry, whoever makes it."""
    assert path_of("c") is not None
    at = [s for s, state in _entries(BOUND) if state in ("landed", "planted", "gathered")]
    assert len(at) > 30
    presses = [e for s in at[:12] for e in (_key(s, "k"), _key(s + 1, "k", False))]
    _paths(lambda: _with(read_log(BOUND), list(presses)), path_of)


# a top-level key that sends the near hip somewhere over 0.3 s (a blend): pressed in
# flight, it travels as `landed` and `planted` are entered - `plant` writes the hip's
# target (owners.take lets the blend go): Python's to enter (pk_pose_fits)
BLEND_KEY = "  - {key: x, set: {hip_near: 30}, over: 0.3, description: a blend}\n"


def _blending(log, steps):
    text = log.header["interface_text"]
    old = "  - {key: q, pose: back_up_back"
    assert text.count(old) == 1
    log.header["interface_text"] = text.replace(old, BLEND_KEY + old)
    return _with(log, [e for s in steps for e in (_key(s, "x"), _key(s + 2, "x", False))])


@needs_cc
def test_a_pose_on_a_joint_a_blend_carries_is_pythons(path_of):
    assert path_of("c") is not None
    flights = [s for s, state in _entries(BOUND) if state == "flight"]
    steps = [s + 3 for s in flights[2:8]]
    with_loop = _paths(lambda: _blending(read_log(BOUND), steps), path_of)
    carried = [a[1]["machines"]["main"][0] for a in with_loop
               if ["hip_near", "blend", ""] in a[1]["owners"]]
    assert {"flight", "landed"} <= set(carried), set(carried)  # (across entries)


def _restore_events(checkpoint: int, restore: int, rewind: int | None):
    from puppet.interface import events as ev

    extra = [(checkpoint, ev.action("checkpoint")), (restore, ev.action("restore"))]
    if rewind is not None:
        extra.append((rewind, ev.action("rewind") | {"to_step": rewind - 150}))
    return extra


@needs_cc
def test_a_checkpoint_restored_and_a_rewind_mid_stride(path_of):
    """A checkpoint in flight (a push kept) restored in `planted`, and a rewind of
    150 steps from within a stride: the same bits, states, kept presses and owners
    with the loop, Python's ticks and the pure-Python path."""
    assert path_of("c") is not None
    entries = _entries(BOUND)
    flight = [s for s, state in entries if state == "flight"][5] + 4
    planted = [s for s, state in entries if state == "planted" and s > flight][1] + 2
    landed = [s for s, state in entries if state == "landed" and s > planted][2] + 1

    def make():
        log = read_log(BOUND)
        extra = _restore_events(flight, planted, landed)
        pairs = sorted([p for p in log.pairs() if p[0] < planted] + extra[:2]
                       + [p for p in log.pairs() if p[0] >= flight] + extra[2:],
                       key=lambda p: p[0])
        log.pairs = lambda: pairs
        return log
    _paths(make, path_of)


@needs_cc
def test_a_hot_reload_that_changes_a_pose_mid_stride(path_of):
    """The interface reloaded in flight with another `plant`: the loop's tables are the
    new runtime's (the entries after it write the new pose)."""
    assert path_of("c") is not None
    flight = [s for s, state in _entries(BOUND) if state == "flight"][4] + 3

    def make():
        log = read_log(BOUND)
        old = "shoulder_near: -55, elbow_near: 10, shoulder_far: -61"
        text = log.header["interface_text"]
        assert text.count(old) == 2  # (plant, front_push)
        new = text.replace(old, "shoulder_near: -45, elbow_near: 15, shoulder_far: -51", 1)
        return _with(log, [(flight, {"type": "reload", "text": new})])
    with_loop = _paths(make, path_of)
    assert any(a[0] > flight for a in with_loop)


def _short_buffer(log, seconds: float):
    text = log.header["interface_text"]
    old = "        buffer: 0.3\n"
    assert text.count(old) == 1
    log.header["interface_text"] = text.replace(old, f"        buffer: {seconds}\n")
    return log


@needs_cc
@pytest.mark.parametrize("seconds", [0.02, 0.12])
def test_a_press_kept_too_long_for_its_buffer(seconds, path_of):
    """ctrl+a kept for 0.02 s or 0.12 s only: most presses (made as the cat lands) are
    too old when `ready` is entered (Python's tick there, the press staying kept),
    some not (the loop spends them): the same as Python's ticks either way."""
    with_loop = _paths(lambda: _short_buffer(read_log(BOUND), seconds), path_of)
    assert any(a[1]["buffer"] for a in with_loop)
