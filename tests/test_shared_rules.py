"""Rules written once and used in several places: which keys are live in a state, how
long a scripted run lasts, where the flights in a trajectory are."""

from __future__ import annotations

import numpy as np

from puppet.data.catalog import find
from puppet.data.interfaces import load_interface
from puppet.timeline.expectations.measure import runs as _runs
from puppet.timeline.script import DEFAULT_SECONDS, ScriptSpec, run_seconds


def test_key_map_shows_what_a_key_does_in_the_state():
    from puppet.app.describe import control_rows
    from puppet.app.keymap import pose_key_bindings

    spec, _ = load_interface(find("interface", "luxo-keys"))
    assert dict(pose_key_bindings(spec, "upright"))["1"] == "stand_low"
    # on its back "1" rolls over (the state's key), so the key map shows no stand pose
    assert "1" not in dict(pose_key_bindings(spec, "on_back"))
    assert ("1", "roll over") in control_rows(spec, "on_back")  # the HUD's rows


def test_run_seconds_caller_then_script_then_default():
    script = ScriptSpec(events=[], seconds=3.0)
    assert run_seconds(script, 1.5) == 1.5
    assert run_seconds(script) == 3.0
    assert run_seconds(ScriptSpec(events=[])) == DEFAULT_SECONDS
    assert run_seconds(None) == DEFAULT_SECONDS


def test_runs_are_the_stretches_of_true_samples():
    flags = np.array([1, 1, 0, 1, 0, 0, 1], dtype=bool)
    assert _runs(flags) == [(0, 1), (3, 3), (6, 6)]
    assert _runs(np.zeros(3, dtype=bool)) == []


def test_live_keys_are_what_the_runtime_binds_in_every_state_of_every_interface():
    """The HUD and the key map (describe.live_keys) show what a key does: the binding
    the runtime would run, in every state of every shipped interface."""
    from pathlib import Path

    from puppet.app.describe import live_keys
    from puppet.data.catalog import load_setup
    from puppet.data.keys import normalize_key
    from puppet.session import Session

    for path in sorted((Path(__file__).resolve().parents[1] / "interfaces").glob("*.yaml")):
        session = Session(load_setup(path.stem))
        spec, runtime = session.interface, session.runtime
        for state in spec.states or [None]:
            if state is not None:
                runtime.machine.enter(state, session.steps)
            for k in live_keys(spec, state, session.setup.scene.name):
                assert runtime.binding(normalize_key(k.key)) is k, (path.stem, state, k.key)


def test_longest_run_takes_the_first_of_two_as_long():
    """Two stretches of 10 samples at 120 Hz: their seconds differ by rounding
    (0.075 and 0.07500000000000001), and the first must still be the one."""
    from puppet.timeline.expectations.measure import longest_run as _longest_run

    t = np.arange(40) * 4 * (1 / 480)
    flags = np.zeros(40, dtype=bool)
    flags[0:10] = flags[15:25] = True
    assert t[24] - t[15] > t[9] - t[0]  # the rounding the rule must not follow
    length, first, last = _longest_run(flags, t)
    assert (first, last) == (0, 9)
    assert abs(length - 10 * t[1]) < 1e-12
    flags[30:31] = True  # shorter, later: not it; one sample longer, later: it
    assert _longest_run(flags, t)[1:] == (0, 9)
    flags[25] = True
    assert _longest_run(flags, t)[1:] == (15, 25)
    assert _longest_run(np.zeros(3, dtype=bool), t[:3]) == (0.0, -1, -1)
