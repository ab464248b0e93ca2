"""The compiled kernel on a blown-up state and with a damaged cache: both paths answer
a non-finite state alike (C's NaN, no exception: the session's blow-up check recovers
it), a module cut short in the cache is built again instead of loaded (SIGBUS), and a
failed build is tried again once a compiler is there (found by a review of 98ebcb6).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys

from kernel_paths import needs_cc

from puppet.data.catalog import ROOT, load_character_named, load_scene_named
from puppet.physics import kernel


def _outcome(call):
    try:
        return ("value", repr(call()))
    except Exception as exc:  # noqa: BLE001 - what each path does is the point
        return ("raises", type(exc).__name__)


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
    path_of("c")
    with_kernel = _com_with_infinite_angle()
    path_of("python")
    assert _com_with_infinite_angle() == with_kernel


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
    path_of("c")
    with_kernel = _tracking_with_a_nan_foot()
    path_of("python")
    assert _tracking_with_a_nan_foot() == with_kernel


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
