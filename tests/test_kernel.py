"""The compiled kernel (puppet/physics/kernel.py) and its pure-Python fallback give the
same bits: mocap and walker logs replay to their recorded hashes on either path.

The logs cover the kernel's branches: KD tracking's pulls and targets (the mocap
walk), walking in place (the feet's forward kinematics), a push's reactions with a
protective step, a fall and a get-up (no lifting, the pose on every link's points), a
lost stream stood on, the walkers' centre of mass and its velocity, frame targets,
the support polygon and two-link reaches (a backflip, a handstand, the monkey bars
and the ladder). A test that needs a compiler skips where there is none; CI has gcc.
None reads a clock.
"""

from __future__ import annotations

import os

import pytest
from kernel_paths import needs_cc

from puppet.data.catalog import ROOT
from puppet.physics import kernel
from puppet.testing import replay_log

LOGS = ROOT / "assets" / "logs"
TRACKED = ["biped-mocap-walk", "biped-mocap-in-place", "biped-mocap-push",
           "biped-mocap-fall", "biped-mocap-lost", "biped-walk-mocap-arms",
           "biped-mocap-highbar"]
WALKERS = ["biped-walk", "biped-auto-walk"]
# frame targets (pk_frame), the support polygon (pk_support), two-link reaches
# (pk_two_link) and the add maps of the state-machine walkers and gymnasts
CONTROLLED = ["biped-backflip", "biped-handstand", "biped-monkey-bars", "biped-ladder-climb"]



def _replayed(name: str):
    result = replay_log(str(LOGS / f"{name}.jsonl"))
    return result.final_hash, result.recorded_hash, result.failed


@needs_cc
@pytest.mark.parametrize("name", TRACKED + WALKERS + CONTROLLED)
def test_both_paths_replay_to_the_recorded_hash(name, path_of):
    assert path_of("c") is not None
    with_kernel = _replayed(name)
    assert path_of("python") is None
    in_python = _replayed(name)
    assert with_kernel[0] == in_python[0] == with_kernel[1], (with_kernel, in_python)
    assert not with_kernel[2] and not in_python[2]


def test_python_path_on_request(path_of):
    assert path_of("python") is None
    assert path_of("PYTHON ") is None


@needs_cc
def test_built_into_the_cache_once(tmp_path, monkeypatch, path_of):
    """A fresh cache gets one module, keyed by the source's hash, with its digest, and
    no leftovers (the build's temporary directory is gone); the next process loads it."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert path_of("") is not None
    made = sorted(os.listdir(tmp_path / "puppet"))
    assert len(made) == 2 and all(n.startswith(kernel.key()) for n in made), made
    assert made[1] == made[0] + ".sha256", made
    assert path_of("c") is not None
    assert sorted(os.listdir(tmp_path / "puppet")) == made


def test_no_compiler_falls_back_to_python(tmp_path, monkeypatch, path_of):
    """A build that fails leaves the Python path (and a note, so that the next start
    does not try again); ``PUPPET_KERNEL=c`` makes it an error."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setenv("CC", str(tmp_path / "no-such-compiler"))
    monkeypatch.setattr(kernel, "FLAGS", [*kernel.FLAGS, "-DNO_CC"])  # (a new key)
    assert path_of("") is None
    assert any(n.endswith(".failed") for n in os.listdir(tmp_path / "puppet"))
    monkeypatch.setenv(kernel.ENV, "c")
    kernel.reset()
    with pytest.raises(kernel.KernelError):
        kernel.get()


def _tracker_states(name: str, at: list[int]) -> list:
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(str(LOGS / f"{name}.jsonl"))
    setup, _ = setup_for_log(log)
    session = new_session(log, setup)
    feeder, out, now = LogFeeder(session, log), [], 0
    for step in at:
        feeder.advance(step - now)
        now = step
        out.append(session.runtime.tracker.get_state())
    return out


@needs_cc
def test_the_tracker_keeps_the_same_state_on_both_paths(path_of):
    """What a checkpoint keeps of the tracker (the last sample's link positions, their
    velocities, the feet's turning rates, from the kernel's arrays) is the Python
    path's, in mid-walk and in mid-reaction to a push."""
    at = [1000, 2001, 2600, 3500]
    path_of("c")
    with_kernel = _tracker_states("biped-mocap-push", at)
    path_of("python")
    assert _tracker_states("biped-mocap-push", at) == with_kernel
    assert all(state[5] is not None for state in with_kernel)  # a sample's memory


@needs_cc
def test_two_link_ik_gives_the_same_answers_on_both_paths(path_of):
    """``pk_two_link`` and ``TwoLink``'s Python: the same bits within reach, past it (the
    damped least squares against a limit), and NaN alike on a blown-up target (C's
    answer; Python's math would raise)."""
    import math

    from puppet.interface.ik_two import TwoLink

    def answers():
        two = TwoLink((0.3, 0.25, 0.1, -0.05), ((0.3, 0.03), (0.25, -0.01)),
                      (None, (-2.5, 0.0)), 0.05, 1e-4, 20)
        return [two.solve(d0, d1, -0.5) for d0, d1 in
                [(0.3, 0.2), (0.9, 0.9), (-0.1, 0.05), (0.05, -0.5),
                 (math.inf, 0.0), (0.2, -math.inf), (math.nan, 0.1)]]

    assert path_of("c") is not None
    with_kernel = answers()
    assert path_of("python") is None
    assert repr(answers()) == repr(with_kernel)
    assert any(math.isnan(q) for qs in with_kernel for q in qs)


def _reach_targets(tmp_path) -> list:
    """Luxo's shade reaching for a rail's handholds, a swinging bar it grasps (a moving
    prop's point) and a point steered by two channels: the targets step by step."""
    from test_reach_grasp import LUXO, press, session

    from puppet.interface import events as ev

    s, out = session(tmp_path, LUXO), []
    s.advance(240)
    for key, steps in (("e", 300), ("n", 300), ("s", 200), ("g", 500), ("u", 10)):
        if key == "s":
            s.handle(ev.channels({"hx": 0.8, "hy": 0.3}))
        press(s, key)
        for _ in range(steps // 10):
            s.advance(10)
            out.append([s.character.servos[j].target for j in ("ankle", "knee")])
    return out + [sorted(s.sim.grasps), s.sim.state_hash()]


@needs_cc
def test_reaches_write_the_same_targets_on_both_paths(path_of, tmp_path):
    """``pk_reach_aim`` and ``pk_reach_set`` (the reach's eased point, the chain's IK and
    its writes in one go) and the reach tick's Python: the same bits, for a fixed prop's
    point, a swinging prop's and a steered one."""
    assert path_of("c") is not None
    with_kernel = _reach_targets(tmp_path)
    assert path_of("python") is None
    assert repr(_reach_targets(tmp_path)) == repr(with_kernel)
    assert with_kernel[-2] == ["shade"] or len(with_kernel) > 100
