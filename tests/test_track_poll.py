"""KD tracking's control steps in the kernel's stepping loop (``interface.track_poll``)
do what Python's ticks do: every shipped KD mocap log (walking in place too) replays
to the same tracker state, schedule, servo targets and physics bits, call by call,
with the loop, without it (Python's ticks on the kernel) and on the pure-Python path;
cut into calls of odd lengths too (runs that stop between samples and go on from
there), and through a checkpoint restored in the middle of a run of kernel ticks.
"""

from __future__ import annotations

from unittest.mock import patch

import pytest
from helpers import play_events
from kernel_paths import needs_cc, trace

from puppet.data.catalog import load_setup
from puppet.interface import track_poll
from puppet.interface.runtime import InterfaceRuntime
from puppet.interface.track_poll import TrackPoll
from puppet.mocap.bvh import read_bvh
from puppet.mocap.clip_source import ClipSource
from puppet.mocap.retarget import load_mapping, retarget_clip
from puppet.session import Session
from puppet.timeline.log import read_log

KD_LOGS = ["biped-mocap-in-place", "biped-mocap-walk", "biped-mocap-live", "biped-mocap-lost",
           "biped-mocap-push", "biped-mocap-library", "biped-mocap-fall"]


def _trace(name: str, loop: bool, chunk: int | None = None):
    """``kernel_paths.trace`` of a shipped log (it ends on its recorded hash), the
    control steps the kernel ran and Python's ticks."""
    log = read_log(f"assets/logs/{name}.jsonl")
    ran = [0, 0]
    run, tick = TrackPoll.run, InterfaceRuntime.tick

    def counted(self, *args, **kwargs):
        before = self.kernel_ticks
        s = run(self, *args, **kwargs)
        ran[0] += self.kernel_ticks - before
        return s

    def ticked(self, step):
        ran[1] += 1
        return tick(self, step)
    with patch.object(track_poll.TrackPoll, "run", counted), \
            patch.object(InterfaceRuntime, "tick", ticked):
        out, _, _, _ = trace(log, loop, chunk)
    assert out[-1][-1] == log.end_hash, name
    return out, ran[0], ran[1]


# Every log whole; cut 7 steps a call (a run stopped at every seventh step, off the
# control steps) only where the tracker's own state changes most - walking in place, a
# lost stream, a fall's get-up: the other KD logs' samples cut off the control steps are
# test_poll_track_samples' (its edited streams), which came later and covers them.
CUT = [(name, None) for name in KD_LOGS] + [
    (name, 7) for name in ("biped-mocap-in-place", "biped-mocap-lost", "biped-mocap-fall")]


@needs_cc
@pytest.mark.parametrize(("name", "chunk"), CUT)
def test_the_loop_does_what_the_tracker_ticks_do(name, chunk, path_of):
    assert path_of("c") is not None
    with_loop, ticks, python = _trace(name, loop=True, chunk=chunk)
    # the kernel ran the tracker's control steps: standing while lost, the way back,
    # a reaction, a protective step, a get-up, a library's window, walking in place;
    # Python's ticks are the rare ones (the stream lost, a push judged, a get-up or a
    # window begun and ended)
    assert ticks > 100, ticks
    if chunk is None:
        assert python <= 30, python
    in_ticks, none, python = _trace(name, loop=False, chunk=chunk)
    assert none == 0 and python > ticks
    assert path_of("python") is None
    in_python, none, _ = _trace(name, loop=True, chunk=chunk)
    assert none == 0  # no kernel, no loop
    assert len(with_loop) == len(in_ticks) == len(in_python)
    for a, b, c in zip(with_loop, in_ticks, in_python):
        assert a == b == c, (a, b, c)


@pytest.fixture(scope="module")
def walk():
    return retarget_clip(read_bvh("assets/mocap/cmu-131_01-walk.bvh"),
                         load_mapping("assets/mappings/cmu-131.yaml"))


def _play(session, events, until_step):
    """The events at their steps, the steps in calls of 5 (runs cut between samples)."""
    play_events(session, events, until_step, chunk=5)


def _restored(walk) -> tuple[str, str, int]:
    """A clip followed, a checkpoint in the middle of it, then played on and played
    again from the checkpoint: both hashes, and the control steps the kernel ran."""
    s = Session(load_setup("biped-mocap"))
    events = ClipSource(walk).events(s.sim.dt, 2.0)
    _play(s, events, 482)  # (mid-way between two samples)
    s.checkpoint()
    rest = [e for e in events if e[0] >= 482]
    _play(s, rest, 900)
    first = s.sim.state_hash()
    s.restore_checkpoint()
    _play(s, rest, 900)
    poll = s.runtime.poll
    return first, s.sim.state_hash(), 0 if poll is None else poll.kernel_ticks


@needs_cc
def test_a_checkpoint_between_samples_replays_to_the_bit(walk, path_of):
    assert path_of("c") is not None
    first, again, ticks = _restored(walk)
    assert first == again and ticks > 0
    assert path_of("python") is None
    first_py, again_py, none = _restored(walk)
    assert (first_py, again_py, none) == (first, again, 0)


def test_no_track_loop_on_the_python_path(path_of):
    from puppet.timeline.replay import new_session, setup_for_log

    assert path_of("python") is None
    log = read_log("assets/logs/biped-mocap-walk.jsonl")
    assert new_session(log, setup_for_log(log)[0]).runtime.poll is None
