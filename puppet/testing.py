"""Helpers for test suites: replay a log, record a scripted performance.

    from puppet.testing import replay_log

    result = replay_log("assets/logs/luxo-hop.jsonl")
    assert not result.failed, [str(f) for f in result.failed]
    base = result.trajectory.index("base")
    assert result.trajectory.y[:, base].max() > 0.1

``ReplayResult`` has the final state hash, the trajectory (numpy arrays of time,
per-link x/y/angle, joint angles and targets, the interface's state and mode...), the
summary and the failed expectations (each with what was measured).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from puppet.data.catalog import find, load_setup
from puppet.session import Session
from puppet.timeline.expectations import Outcome, evaluate_all, parse_expectations
from puppet.timeline.log import Log, Recorder, read_log, record_events
from puppet.timeline.replay import SAMPLE_EVERY, ReplayResult, Trajectory, replay
from puppet.timeline.script import compile_script, load_script, run_seconds

__all__ = ["ReplayResult", "Trajectory", "Outcome", "replay_log", "record_script",
           "check", "Recorder", "read_log"]


def replay_log(path: str | Path | Log, until_step: int | None = None, allow_truncated: bool = False,
               expect: list | None = None, sample_every: int = SAMPLE_EVERY,
               as_recorded: bool = False) -> ReplayResult:
    """Replay ``path`` (or a log already read) headless and check its expectations
    (header or sidecar file).

    ``expect`` (a list of expectation dicts, as in a sidecar file) replaces the log's.
    As ``puppet replay --check``: a log without its end line is refused (DataError)
    unless ``allow_truncated``, which checks the events it has (``result.unchecked``
    says what was left out).
    """
    return replay(path, until_step, allow_truncated, sample_every=sample_every,
                  as_recorded=as_recorded, expect=expect)


def check(result: ReplayResult, expect: list) -> list[Outcome]:
    """Evaluate more expectations on a finished replay; returns the failed ones."""
    items = parse_expectations(expect)
    items.check_links(result.trajectory.links)
    return [o for o in evaluate_all(items.items, result.trajectory, result.final_hash)
            if not o.passed]


def record_script(script: str, path: str | Path, interface: str | None = None,
                  scene: str | None = None, seconds: float | None = None,
                  expect: list | None = None, description: str | None = None) -> Path:
    """Run a scripted performance (assets/scripts/NAME.yaml or a path) headless and
    record it as a log at ``path``."""
    spec = load_script(find("script", script))
    iface = interface or spec.interface
    if iface is None:
        raise ValueError(f"script '{script}' names no interface; pass interface=")
    session = Session(load_setup(iface, scene or spec.scene))
    events = compile_script(spec, session.sim.dt)
    until = round(run_seconds(spec, seconds) / session.sim.dt)
    return record_events(session, events, until, path, expect=expect,
                         description=description or spec.description or None)


def replay_script_text(text: str, interface: str | Path, expect: str | Path) -> ReplayResult:
    """Play a script given as text (a search's candidate) through ``interface``, record
    it, and replay the log judged by the expectations file ``expect`` (a shipped log's
    sidecar): a tuning tool scores each try exactly as the tests check the log."""
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "try.yaml"
        script.write_text(text, encoding="utf-8")
        log = Path(tmp) / "try.jsonl"
        record_script(str(script), log, interface=str(interface))
        (Path(tmp) / "try.expect.yaml").write_text(Path(expect).read_text(encoding="utf-8"),
                                                   encoding="utf-8")
        return replay_log(log)
