"""Helpers for test suites: replay a log, record a scripted performance.

    from puppet.testing import replay_log

    result = replay_log("assets/logs/luxo-hop.jsonl")
    assert not result.failed, [str(f) for f in result.failed]
    base = result.trajectory.index("base")
    assert result.trajectory.y[:, base].max() > 0.1

``ReplayResult`` has the final state hash, the trajectory (numpy arrays of time,
per-link x/y/angle, joint angles and targets, the interface's state and mode...), the
summary and the failed expectations (each an ``Outcome``: its ``kind``, what was
expected and what was measured). A bad log or bad expectations raise ``DataError``
(file:line and what is wrong in ``str()``).

A failure test - the physics made weaker, the log must then fail - replays on a
changed Setup (``adjust``: a function of the Setup returning the one to replay on):

    from puppet.testing import replay_log, weaker_joints

    result = replay_log("assets/logs/biped-push-step.jsonl",
                        adjust=weaker_joints(["hip_near", "hip_far"], 0.3))
    assert result.failed  # with 30% of the hips' strength it falls (never_fell...)

``weaker_joints`` scales the named joints' maximum torque (the character's
``max_torque``) in the Setup's character; any other change of the interface or the
character is made the same way (``dataclasses.replace`` / ``model_copy`` of the Setup's
parts).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from puppet.data.catalog import find, load_setup
from puppet.data.errors import DataError
from puppet.session import Session
from puppet.timeline.expectations import (
    Outcome,
    evaluate_all,
    load_expectations,
    parse_expectations,
)
from puppet.timeline.log import Log, Recorder, read_log, record_events
from puppet.timeline.replay import ReplayResult, replay
from puppet.timeline.script import compile_script, load_script, run_seconds
from puppet.timeline.trajectory import Trajectory

__all__ = ["ReplayResult", "Trajectory", "Outcome", "DataError", "replay_log",
           "record_script", "check", "weaker_joints", "Recorder", "read_log"]

# the command line's option, as the replay's errors name it, and its Python spelling
_OPTION, _KEYWORD = "--allow-truncated", "allow_truncated=True"


def _in_python(exc: DataError) -> DataError:
    """A cut log's refusal in the words of this API: ``allow_truncated=True`` where
    the command line's error says ``--allow-truncated``."""
    if _OPTION not in exc.message:
        return exc
    return DataError(exc.path, exc.line, exc.col, exc.message.replace(_OPTION, _KEYWORD))


def _entries(expect, where: str) -> list | None:
    """``expect`` as a list of entries, else a DataError that says one is expected
    (a bare name or one dict is not a list of them)."""
    if expect is None or isinstance(expect, (list, tuple)):
        return expect
    return parse_expectations(expect, where)  # raises: it says what is expected


def replay_log(path: str | Path | Log, until_step: int | None = None, allow_truncated: bool = False,
               expect: list | None = None, sample_every: int | None = None,
               as_recorded: bool = False, adjust=None) -> ReplayResult:
    """Replay ``path`` (or a log already read) headless and check its expectations
    (the sidecar file ``NAME.expect.yaml``, else the header's; the sidecar wins, and a
    header's entries it leaves out are a warning in ``result.warnings``).

    ``expect`` (a list of expectation dicts, as in a sidecar file) replaces the log's.
    As ``puppet replay --check``: a log without its end line is refused (DataError)
    unless ``allow_truncated``, which checks the events it has (``result.unchecked``
    says what was left out). ``adjust``: a function of the Setup returning the one to
    replay on (``replay``'s; see ``weaker_joints`` and the module's example).
    """
    expect = _entries(expect, f"{getattr(path, 'path', path)} (expect=)")
    try:
        log = path if isinstance(path, Log) else read_log(path, allow_truncated)
        result = replay(log, until_step, allow_truncated, sample_every=sample_every,
                        as_recorded=as_recorded, expect=expect, adjust=adjust)
    except DataError as exc:
        raise _in_python(exc) from None
    if expect is None:
        result.warnings += load_expectations(log.path, log.header).notes
    return result


def weaker_joints(joints: list[str], scale: float):
    """An ``adjust`` for ``replay_log``: the Setup with the named joints' maximum torque
    (the character's ``max_torque``) times ``scale``: the physics made weaker, for a
    test that a log fails without the strength it was recorded with."""
    import dataclasses

    def adjust(setup):
        character = setup.character
        names = [j.name for j in character.actuated]
        unknown = [n for n in joints if n not in names]
        if unknown:
            raise DataError(str(setup.character_path), None, None,
                            f"weaker_joints: no driven joint {', '.join(map(repr, unknown))}; "
                            f"the character's are: {', '.join(names)}")
        changed = [j.model_copy({"pd": j.pd.model_copy({"max_torque": j.pd.max_torque * scale})})
                   if j.name in joints else j for j in character.joints]
        return dataclasses.replace(setup, character=character.model_copy({"joints": changed}))

    return adjust


def check(result: ReplayResult, expect: list) -> list[Outcome]:
    """Evaluate more expectations (a list of entries, as in a sidecar file) on a
    finished replay; returns the failed ones."""
    items = parse_expectations(expect, "check(expect=)")
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
