"""Rules written once and used in several places: which keys are live in a state, how
long a scripted run lasts, where the flights in a trajectory are."""

from __future__ import annotations

import numpy as np

from puppet.data.catalog import find
from puppet.data.interfaces import load_interface
from puppet.timeline.expectations import _runs
from puppet.timeline.script import DEFAULT_SECONDS, ScriptSpec, run_seconds


def test_key_map_shows_what_a_key_does_in_the_state():
    from puppet.app.keymap import pose_key_bindings
    from puppet.app.describe import interface_lines

    spec, _ = load_interface(find("interface", "luxo-keys"))
    assert dict(pose_key_bindings(spec, "upright"))["1"] == "stand_low"
    # on its back "1" rolls over (the state's key), so the key map shows no stand pose
    assert "1" not in dict(pose_key_bindings(spec, "on_back"))
    assert ("1", "roll over") in interface_lines(spec, "on_back")


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

    from puppet.data.catalog import load_setup
    from puppet.data.keys import normalize_key
    from puppet.app.describe import live_keys
    from puppet.session import Session

    for path in sorted((Path(__file__).resolve().parents[1] / "interfaces").glob("*.yaml")):
        session = Session(load_setup(path.stem))
        spec, runtime = session.interface, session.runtime
        for state in spec.states or [None]:
            if state is not None:
                runtime.machine.enter(state, session.steps)
            for k in live_keys(spec, state):
                assert runtime.binding(normalize_key(k.key)) is k, (path.stem, state, k.key)
