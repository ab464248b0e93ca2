"""The kernel's stepping loop holds a biped's frame targets (``FrameTargets.tick``, the
world-held and relative joints re-solved from the links' angles at every control step)
as Python's ticks do: the biped logs whose states poll at every step with joints held
in the world (or reached over time, a blend's travelling angle held by the frame
targets) replay call by call to the same states, held targets, servo targets and
physics bits with the loop, without it (Python's ticks on the kernel) and on the
pure-Python path, fed all at once and a few steps a call (runs that stop at a call's
end and go on from there); and a link's angle made NaN or infinite there is solved
into the same targets, to the bit, on every path.
"""

from __future__ import annotations

import math
import struct
from unittest.mock import patch

import pytest
from kernel_paths import agree_without_the_loop, needs_cc, trace

from puppet.interface import poll_plan
from puppet.timeline.log import read_log
from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

# the walk-up long jump (its walk polls at 480 Hz, hips and ankles held in the world),
# the back flip, the handstand and the kip (world-held waists and split legs), and the
# automatic walk (its frame maps hold the joints anew at each input event: the plan's
# angles written again, the rest of it kept)
HELD = ["biped-longjump", "biped-backflip", "biped-handstand", "biped-kip",
        "biped-auto-walk"]


def _bits(values) -> list[bytes]:
    """Floats as their bits (NaN included: == would not say two NaNs agree)."""
    return [struct.pack("<d", v) for v in values]


def _traces(name: str, path_of, chunk: int | None) -> int:
    """The three paths' traces of ``name`` agree; returns how many of the loop's runs
    had a frame target's angle travelling."""
    log = read_log(f"assets/logs/{name}.jsonl")
    assert path_of("c") is not None
    with_loop, runs, frames, travelling = trace(log, True, chunk)
    assert frames > 0, (runs, frames)  # the loop re-solved frame targets
    agree_without_the_loop(log, with_loop, chunk, path_of)
    return travelling


@needs_cc
@pytest.mark.parametrize("name", HELD)
def test_the_loop_holds_frame_targets_as_the_ticks_do(name, path_of):
    travelling = _traces(name, path_of, None)
    if name in ("biped-backflip", "biped-kip"):  # poses reached over time, held in
        assert travelling > 0  # the world all the way (BlendController._write's holds)


@needs_cc
@pytest.mark.parametrize("name", ["biped-longjump", "biped-backflip"])
def test_runs_cut_at_each_call_hold_them_alike(name, path_of):
    """Fed 37 steps a call: each run stops at its call's end and the next goes on
    from there (``tick_first``), the frame targets re-solved at that step too, and a
    travelling one's hold handed back at each run's end as the blend's last."""
    _traces(name, path_of, 37)


# (log, step, state there, a joint held in the world there): the long jump's walk
# (hips and an ankle held, the loop running), the back flip's set (its hips, ankles and
# waist travelling to world-held angles)
AT = {"biped-longjump": (650, "adown_near", "hip_near"),
      "biped-backflip": (800, "flip_set", "hip_far")}


def _non_finite(name: str, link: str, value: float, loop: bool):
    """``name`` replayed to its ``AT`` step, ``link``'s angle set to ``value``, then 6
    steps a call at a time: after each, the servo targets' bits, the held frame
    targets, the machine's state and the physics' hash; and how many of the loop's
    runs re-solved frame targets."""
    step, state, joint = AT[name]
    log = read_log(f"assets/logs/{name}.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    LogFeeder(session, log).advance(step)
    rt = session.runtime
    assert rt.machines["main"].current == state and joint in rt.frames.held
    if not loop:
        rt.poll = None
    session.sim.character.bodies[link].angle = value
    run, frames = poll_plan.PollPlan.run, [0]

    def counted(self, *args, **kwargs):
        frames[0] += self.plan.n_frame > 0
        return run(self, *args, **kwargs)
    out = []
    with patch.object(poll_plan.PollPlan, "run", counted):
        for _ in range(6):
            session.advance(1)
            out.append((session.sim.steps, rt.machines["main"].current,
                        _bits(s.target for s in session.character.servos.values()),
                        rt.frames.get_state(), session.sim.state_hash()))
    return out, frames[0]


def _alike(kernel_bits: list[bytes], python_bits: list[bytes]) -> bool:
    """The same targets, a NaN where the other has one: a NaN's sign bit may differ
    after C's and Python's arithmetic order it differently (``kernel.cos``'s note; no
    hash of a blown-up state is judged, and the state hashes must agree)."""
    for a, b in zip(kernel_bits, python_bits, strict=True):
        x, y = struct.unpack("<d", a)[0], struct.unpack("<d", b)[0]
        if a != b and not (math.isnan(x) and math.isnan(y)):
            return False
    return True


@needs_cc
@pytest.mark.parametrize("name,link,value", [
    ("biped-longjump", "pelvis", math.nan), ("biped-longjump", "thigh_near", math.inf),
    ("biped-longjump", "chest", -math.inf), ("biped-backflip", "thigh_far", math.nan),
    ("biped-backflip", "pelvis", math.inf)])
def test_a_non_finite_angle_is_held_alike_on_every_path(name, link, value, path_of):
    """A held joint's parent, child or the chest made NaN or infinite, held or
    travelling: the kernel's ``pk_frame`` in the loop writes the bits it writes in
    Python's tick, and Python's solve (its ``remainder`` answering as libm's) the same
    targets, NaN for NaN; the states, the held targets and the session's recovery are
    the same on every path."""
    assert path_of("c") is not None
    with_loop, frames = _non_finite(name, link, value, True)
    assert frames > 0  # the loop solved them on the non-finite state
    assert any(math.isnan(struct.unpack("<d", b)[0]) for b in with_loop[0][2])
    ticks, none = _non_finite(name, link, value, False)
    assert none == 0
    assert with_loop == ticks  # the kernel's two ways: to the bit
    assert path_of("python") is None
    in_python, none = _non_finite(name, link, value, True)
    assert none == 0
    assert len(in_python) == len(with_loop)
    for (step, state, bits, *rest), (step2, state2, bits2, *rest2) in zip(with_loop,
                                                                         in_python):
        assert (step, state, rest) == (step2, state2, rest2)
        assert _alike(bits, bits2), step


@needs_cc
def test_a_run_cut_by_an_input_event_goes_on_at_the_next_tick(path_of):
    """The automatic walk's input events (about one every 2 steps, its control period
    4), when the kernel's loop does not apply them (``session.event_runs``: here
    turned off; an event it cannot apply, a key press), cut the loop's runs between its
    ticks: the session steps on to the next tick as the loop would, and the kernel does
    that tick (``tick_first``), no Python tick between; the traces above hold it to the
    Python path's bits."""
    assert path_of("c") is not None
    from puppet.session import event_runs

    log = read_log("assets/logs/biped-auto-walk.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    run, seen = poll_plan.PollPlan.run, []

    def recorded(self, space, dt, now, *args):
        s = run(self, space, dt, now, *args)
        seen.append((now, args[-1], s))
        return s
    with patch.object(poll_plan.PollPlan, "run", recorded), \
            patch.object(event_runs.EventRuns, "start", lambda *args, **kwargs: None):
        LogFeeder(session, log).advance(log.last_step)
    later = sum(1 for (_, _, end), (now, first, _) in zip(seen, seen[1:])
                if first and now > end)
    assert later > len(seen) // 2, (later, len(seen))
    assert session.sim.state_hash() == log.end_hash
