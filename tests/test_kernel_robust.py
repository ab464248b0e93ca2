"""The compiled kernel on a blown-up state and with a damaged cache: both paths answer
a non-finite state alike (C's NaN, no exception: the session's blow-up check recovers
it), a module cut short in the cache is built again instead of loaded (SIGBUS), and a
failed build is tried again once a compiler is there (found by a review of 98ebcb6).
"""

from __future__ import annotations

import math
import os
import struct
import subprocess
import sys

import pytest
from kernel_paths import needs_cc

from puppet.data.catalog import ROOT, load_character_named, load_scene_named
from puppet.physics import kernel


def _outcome(call):
    try:
        return ("value", repr(call()))
    except Exception as exc:  # noqa: BLE001 - what each path does is the point
        return ("raises", type(exc).__name__)


def _same_on_both_paths(path_of, run):
    """``run()`` on the compiled kernel and on the pure-Python path: the two answers
    must be equal; the kernel's is returned."""
    path_of("c")
    with_kernel = run()
    path_of("python")
    assert run() == with_kernel
    return with_kernel


def _com_with_infinite_angle():
    from puppet.physics.simulation import Simulation

    spec = load_character_named("biped")
    sim = Simulation(spec[0] if isinstance(spec, tuple) else spec,
                     load_scene_named("flat")[0])
    c = sim.character
    c.bodies[c.root].angle = math.inf
    return _outcome(c._com)


@needs_cc
def test_com_of_a_non_finite_state_is_the_same_on_both_paths(path_of):
    _same_on_both_paths(path_of, _com_with_infinite_angle)


def _tracking_with_a_nan_foot():
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(str(ROOT / "assets" / "logs" / "biped-mocap-walk.jsonl"))
    setup, _ = setup_for_log(log)
    session = new_session(log, setup)
    feeder = LogFeeder(session, log)
    feeder.advance(1000)
    foot = next(iter(session.runtime.tracker.soles))
    session.sim.character.bodies[foot].angle = math.nan

    def go():
        feeder.advance(8)
        return session.sim.steps
    return _outcome(go)


@needs_cc
def test_a_nan_foot_under_tracking_is_handled_the_same_on_both_paths(path_of):
    _same_on_both_paths(path_of, _tracking_with_a_nan_foot)


@needs_cc
def test_a_truncated_cached_module_falls_back(tmp_path, path_of):
    good = kernel.cache_dir()
    path_of("c")  # built (or found) in the usual cache
    import sysconfig
    name = kernel.key() + sysconfig.get_config_var("EXT_SUFFIX")
    (tmp_path / "puppet").mkdir()
    with open(os.path.join(good, name), "rb") as f:
        (tmp_path / "puppet" / name).write_bytes(f.read(2000))
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path), **{kernel.ENV: ""})
    run = subprocess.run([sys.executable, "-c", "from puppet.physics import kernel; "
                          "print(kernel.get() is not None)"], env=env, capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0, run.returncode  # (-7: SIGBUS)


@needs_cc
def test_a_failed_build_is_tried_again_once_a_compiler_is_there(tmp_path, monkeypatch,
                                                                  path_of):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(kernel, "FLAGS", [*kernel.FLAGS, "-DREVIEW"])  # (a fresh key)
    monkeypatch.setenv("CC", str(tmp_path / "no-such-compiler"))
    assert path_of("") is None
    monkeypatch.delenv("CC")  # the compiler is there now (a later start)
    assert path_of("") is not None


def _answers(solve, *args):
    try:
        return ["nan" if q != q else struct.pack("<d", q).hex() for q in solve(*args)]
    except ArithmeticError as exc:
        return type(exc).__name__


@needs_cc
def test_two_link_answers_a_blown_up_target_alike_on_both_paths(path_of):
    """A blown-up reach target: both paths answer NaN where the other does and the same
    bits elsewhere, no exception (the NaN's sign bit may differ: docs in kernel.cos)."""
    from puppet.interface.ik_two import TwoLink

    def answers():
        two = TwoLink((0.3, 0.25, 0.1, -0.05), ((0.3, 0.03), (0.25, -0.01)),
                      (None, (-2.5, 0.0)), 0.05, 1e-4, 20)
        return [_answers(two.solve, d0, d1, -0.5) for d0, d1 in
                [(math.inf, 0.0), (0.2, -math.inf), (math.nan, 0.1), (0.1, math.nan)]]

    assert path_of("c") is not None
    with_kernel = answers()
    assert path_of("python") is None
    assert answers() == with_kernel


def test_a_chain_with_a_link_of_no_length_is_refused_where_it_is_written(tmp_path):
    """IK divides by each link's length: a chain whose end sits on its last joint's
    anchor is an error at load (file:line), not a crash on one path and a reach on the
    other."""
    from puppet.data.catalog import load_setup
    from puppet.data.errors import DataError

    text = (ROOT / "interfaces" / "biped-ladder.yaml").read_text().replace(
        "hand_near: {joints: [shoulder_near, elbow_near], end: [0.01, 0.69]}",
        "hand_near: {joints: [shoulder_near, elbow_near], end: [0.0, 1.1065]}")
    assert "end: [0.0, 1.1065]" in text
    path = tmp_path / "zero.yaml"
    path.write_text(text)
    with pytest.raises(DataError, match=r"zero.yaml:\d+:\d+: chain 'hand_near': its link 2 "
                                        r"has no length"):
        load_setup(str(path))


def _blown_up_replay(name: str, step: int, link: str) -> tuple[int, int]:
    """A shipped log replayed to ``step``, ``link``'s angle made infinite, 2000 more
    steps: how many recoveries the session made (a checkpoint restored each) and where it is."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(f"assets/logs/{name}.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    LogFeeder(session, log).advance(step)
    session.sim.character.bodies[link].angle = math.inf
    session.advance(2000)
    return len(session.blowup_messages), session.sim.steps


@needs_cc
@pytest.mark.parametrize("name, step, link", [("biped-auto-walk", 3000, "thigh_near"),
                                              ("biped-ladder-climb", 1000, "chest")],
                         ids=["feedback-add-maps", "reach"])
def test_an_infinite_angle_under_feedback_or_a_reach_recovers_on_both_paths(
        path_of, name, step, link):
    """Feedback's angle sensors and a reach's rotation run in the kernel (libm: NaN) and
    in Python (``kernel.remainder``, ``kernel.cos``: NaN, where ``math`` raised): both
    paths reach the session's blow-up check and restore a checkpoint."""
    with_kernel = _same_on_both_paths(path_of, lambda: _blown_up_replay(name, step, link))
    assert with_kernel[0] >= 1, with_kernel  # it did blow up, and was recovered
