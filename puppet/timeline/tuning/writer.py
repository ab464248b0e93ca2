"""What a search leaves: the best performance as a log (``NAME.jsonl``), its sidecar
(``NAME.expect.yaml``: the spec's feat), the script that plays it (when the search
began from the scene's start: a log's input is not script entries) and, when the
interface's numbers were varied, the interface as tuned (``NAME.interface.yaml``, the
original file with those numbers changed in place, comments kept).

The log is recorded by playing the kept input into a fresh session with a ``Recorder``,
as ``puppet play --record`` records a script, and then replayed from the file with its
sidecar (``puppet replay --check``'s replay): what the report says is what the file
does. Each file is written beside and then renamed over the old one.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from puppet.timeline.tuning.search import TuneResult
from puppet.timeline.tuning.spec import Loaded


@dataclass
class Written:
    log: Path
    sidecar: Path | None = None
    script: Path | None = None
    interface: Path | None = None
    outcomes: list = field(default_factory=list)  # the replayed log's expectations
    same_as_search: bool = True  # the replay ended on the state the search reached
    notes: list[str] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(o.passed for o in self.outcomes)


def _replace(tmp: Path, path: Path) -> None:
    os.replace(tmp, path)


def write_all(loaded: Loaded, result: TuneResult, log_path: Path,
              script_path: Path | None = None) -> Written:
    log_path = Path(log_path)
    log_path.parent.mkdir(parents=True, exist_ok=True)
    out = Written(log_path)
    if result.interface_text is not None:
        out.interface = log_path.with_name(log_path.name.removesuffix(".jsonl")
                                           + ".interface.yaml")
        _text(out.interface, result.interface_text)
    final = _record(loaded, result, log_path)
    feat = loaded.located.data.get("feat") if isinstance(loaded.located.data, dict) else None
    side = log_path.with_name(log_path.name.removesuffix(".jsonl") + ".expect.yaml")
    if feat is not None:
        body = {"description": (feat.get("description") or loaded.spec.description).strip()}
        body.update({k: v for k, v in feat.items() if k != "description"})
        _text(side, f"# The feat of {loaded.path.as_posix()}, judged on {log_path.name}\n"
                    + yaml.safe_dump(body, sort_keys=False, width=88))
        out.sidecar = side
    elif side.is_file():  # an older search's sidecar would judge this log by other rules
        side.unlink()
    if script_path is not None:
        if result.start is None or result.start.entries is None:
            out.notes.append("no script written: the search began from a log, whose input "
                             "is not script entries (the log is the performance)")
        else:
            _text(Path(script_path), script_text(loaded, result, log_path))
            out.script = Path(script_path)
    from puppet.timeline.replay import replay

    replayed = replay(log_path, check=True)
    out.outcomes = replayed.outcomes
    out.same_as_search = replayed.final_hash == final
    out.notes += replayed.warnings
    return out


def _text(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text, encoding="utf-8")
    _replace(tmp, path)


def _record(loaded: Loaded, result: TuneResult, log_path: Path) -> str:
    """The kept input played into a fresh session with a Recorder; the end state hash."""
    from puppet.session import Session
    from puppet.session.playback import play
    from puppet.timeline.log import Recorder
    from puppet.timeline.tuning.trial import _setup

    start = result.start
    session = Session(_setup(start.setup_from), dt=start.dt,
                      checkpoint_interval=start.interval)
    tmp = log_path.with_name(log_path.name + ".tmp")
    tmp.unlink(missing_ok=True)
    description = loaded.spec.description or None
    with Recorder(session, tmp, description=description):
        play(session, result.pairs, result.end_step)
    _replace(tmp, log_path)
    return session.sim.state_hash()


def _flow(entry: dict) -> str:
    """One entry on one line, as the shipped scripts are written."""
    def value(v):
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k}: {value(x)}" for k, x in v.items()) + "}"
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, str):
            return json.dumps(v) if not v.replace("+", "").replace("_", "").isalnum() else v
        return repr(v) if isinstance(v, float) else str(v)
    return value(entry)


def script_text(loaded: Loaded, result: TuneResult, log_path: Path) -> str:
    """The performance as a script (``puppet play --input``): the fixed events, then
    each kept stage's checkpoint and entries, a comment naming the stage."""
    spec = loaded.spec
    start = result.start
    head = {"description": spec.description} if spec.description else {}
    lines = [yaml.safe_dump(head, width=100).rstrip()] if head else []
    lines.append(f"# Found by puppet tune {loaded.path.as_posix()} (seed {spec.seed}); "
                 f"recorded as {log_path.name}.")
    if start.performer is not None:  # the clip is not in the script: the command adds it
        lines.append(f"# A clip plays along: puppet play {spec.interface} --headless "
                     f"{start.performer.command} --input SCRIPT")
    lines += [f"interface: {spec.interface}"]
    if spec.scene:
        lines.append(f"scene: {spec.scene}")
    lines += [f"seconds: {round(result.seconds, 4)}", "events:"]
    for e in start.entries:
        lines.append(f"  - {_flow(e)}")
    for k in result.kept:
        stage = spec.stages[k.stage]
        rep = f" #{k.rep + 1}" if stage.times > 1 or stage.until else ""
        lines.append(f"  # {stage.name}{rep}")
        lines.append(f"  - {_flow({'t': k.t0, 'action': 'checkpoint'})}")
        for e in k.entries:
            lines.append(f"  - {_flow(e)}")
    return "\n".join(lines) + "\n"
