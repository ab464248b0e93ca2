"""Input logs (JSON Lines): what was done to a session, step by step, to replay it.

Line 1 is a header; then one line per event, in the order the session applied them;
on a clean exit a last line with the final step and state hash:

    {"format": "puppet-log", "version": 1, "puppet": "0.1.0", "interface": "luxo-mouse",
     "interface_hash": "...", "character": "luxo", "character_hash": "...",
     "scene": "flat", "scene_hash": "...", "dt": 0.00208..., "seed": 0, "slowdown": 1.0,
     "checkpoint_interval": 1.0, "description": "...", "expect": [...]}
    {"step": 0, "event": {"type": "mouse", "x": 0.5, "y": 0.5}}
    {"step": 960, "event": {"type": "action", "name": "rewind", "to_step": 480}}
    {"end": 1200, "hash": "0123456789abcdef"}

Steps may go back (after a rewind): events replay in file order. The file is written
as the session goes and flushed after every line, so a killed process keeps all of it.
"""

from __future__ import annotations

import datetime
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from puppet import __version__
from puppet.data.catalog import FOLDERS, ROOT, Setup, file_hash
from puppet.data.interfaces import (CHECKPOINT_EVERY, CHECKPOINT_MAX, CHECKPOINT_MIN,
                                    MAX_SLOWDOWN, MIN_SLOWDOWN)
from puppet.data.errors import DataError
from puppet.interface.events import Event

FORMAT = "puppet-log"
VERSION = 1
RECORDINGS = FOLDERS["recording"][0]  # where (under the root) the window records to

EVENT_FIELDS = {  # event type -> required fields (besides "type")
    "mouse": ("x", "y"),
    "key": ("key", "down"),
    "action": ("name",),
    "drag": ("phase",),
    "push": ("link", "impulse"),  # a shove: an impulse at a point of a link
    "mouse_button": ("button", "down"),  # interface inputs (puppet/interface/events.py)
    "gamepad": ("name", "value"),
    "channel": ("name", "value"),
    "channels": ("values",),  # many named channels at one step (a mocap frame)
    "reload": ("text",),  # a hot reload: the interface's whole new text
    "gesture": ("key", "path"),  # bind a recorded mouse path to a key
}


def _name(path: Path, kind: str) -> str:
    """How a log names a data file: its catalog name if it is the catalog's file of
    that name, else its absolute path (a relative one would only resolve from the
    directory the recording was made in)."""
    sub, ext = FOLDERS[kind]
    path = Path(path)
    try:
        if path.resolve() == (ROOT / sub / (path.stem + ext)).resolve():
            return path.stem
        return str(path.resolve())
    except OSError:
        return str(path.absolute())


def make_header(session, slowdown: float | None = None, description: str | None = None,
                expect: list | None = None) -> dict:
    """The header of a log. It keeps the interface file's text (``interface_text``),
    so the log can replay the interface as recorded (``--as-recorded``), and from
    anywhere once the file is moved or deleted (a hot reload edits it while recording)."""
    setup: Setup = session.setup
    header: dict[str, Any] = {
        "format": FORMAT,
        "version": VERSION,
        "puppet": __version__,
        "interface": _name(setup.interface_path, "interface"),
        "interface_hash": file_hash(Path(setup.interface_path)),
        "character": _name(setup.character_path, "character"),
        "character_hash": file_hash(Path(setup.character_path)),
        "scene": _name(setup.scene_path, "scene"),
        "scene_hash": file_hash(Path(setup.scene_path)),
        "dt": session.sim.dt,
        "seed": 0,  # nothing is random yet; kept so that logs stay readable if it is
        "slowdown": float(slowdown if slowdown is not None else setup.interface.slowdown),
        "checkpoint_interval": session.checkpoint_interval,
    }
    header["interface_text"] = Path(setup.interface_path).read_text(encoding="utf-8")
    if description:
        header["description"] = description
    if expect:
        header["expect"] = list(expect)
    return header


EXISTS = "exists; choose another path or delete it (a log is never overwritten)"


def default_path(interface_name: str, root: Path | None = None, now=None) -> Path:
    """recordings/<interface>-<YYYYmmdd-HHMMSS>.jsonl, never an existing file."""
    folder = Path(root if root is not None else ROOT) / RECORDINGS
    stamp = (now or datetime.datetime.now()).strftime("%Y%m%d-%H%M%S")
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in interface_name)
    base = folder / f"{safe}-{stamp}"
    path = base.with_suffix(".jsonl")
    n = 2
    while path.exists():
        path = folder / f"{base.name}-{n}.jsonl"
        n += 1
    return path


def _dumps(obj) -> str:
    return json.dumps(obj, separators=(",", ":"), allow_nan=False)


class Recorder:
    """Writes a session's events to a log as they are handled.

    Hooks in as ``session.listener``; ``close()`` writes the end line (clean exit).
    The file is created exclusively (mode 'x'): a log is never silently overwritten,
    not even by a race between checking a path and opening it; an existing ``path``
    is a DataError."""

    def __init__(self, session, path: str | Path, slowdown: float | None = None,
                 description: str | None = None, expect: list | None = None):
        self.session = session
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self.file = self.path.open("x", encoding="utf-8")
        except FileExistsError:
            raise DataError(str(path), None, None, EXISTS) from None
        self._write(make_header(session, slowdown, description, expect))
        self._previous = session.listener
        session.listener = self.on_event

    def _write(self, obj) -> None:
        self.file.write(_dumps(obj) + "\n")
        self.file.flush()

    def on_event(self, step: int, event: Event) -> None:
        if self.file.closed:
            return
        self._write({"step": step, "event": event})
        if self._previous is not None:
            self._previous(step, event)

    def close(self, clean: bool = True) -> None:
        """Stop recording; on a clean exit, write {"end": step, "hash": state hash}."""
        if self.file.closed:
            return
        if clean:
            self._write({"end": self.session.steps, "hash": self.session.sim.state_hash()})
        self.file.close()
        if self.session.listener == self.on_event:
            self.session.listener = self._previous

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        self.close(clean=exc_type is None)


# -- reading -------------------------------------------------------------------------
@dataclass
class LogEvent:
    step: int
    event: Event
    line: int


@dataclass
class Log:
    path: str
    header: dict
    events: list[LogEvent] = field(default_factory=list)
    end: dict | None = None  # {"end": step, "hash": ...} if the session exited cleanly
    truncated_at: int | None = None  # first bad line, when the valid prefix was kept
    truncated_reason: str = ""

    @property
    def end_step(self) -> int | None:
        return None if self.end is None else self.end["end"]

    @property
    def last_step(self) -> int:
        """Where the replay ends: the recorded end, else the last event's step."""
        if self.end_step is not None:
            return self.end_step
        return self.events[-1].step if self.events else 0

    @property
    def end_hash(self) -> str | None:
        return None if self.end is None else self.end.get("hash")

    def pairs(self) -> list[tuple[int, Event]]:
        return [(e.step, e.event) for e in self.events]


def _check_header(path: str, header: Any) -> dict:
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise DataError(path, 1, None, "not a puppet log: line 1 must be a header with "
                                       f'"format": "{FORMAT}"')
    version = header.get("version")
    if version != VERSION:
        raise DataError(path, 1, None, f"log format version {version!r} is not supported: "
                                       f"this puppet ({__version__}) reads version {VERSION}")
    for key, kind in (("interface", str), ("scene", str), ("dt", (int, float))):
        if not isinstance(header.get(key), kind) or isinstance(header.get(key), bool):
            raise DataError(path, 1, None, f"header: '{key}' is missing or not a "
                                           f"{'number' if key == 'dt' else 'string'}")
    if not header["dt"] > 0:
        raise DataError(path, 1, None, f"header: 'dt' must be positive, got {header['dt']}")
    ci = header.setdefault("checkpoint_interval", CHECKPOINT_EVERY)
    if not _is_number(ci) or not CHECKPOINT_MIN <= ci <= CHECKPOINT_MAX:
        raise DataError(path, 1, None, f"header: 'checkpoint_interval' must be a number of "
                                       f"seconds, {CHECKPOINT_MIN:g}..{CHECKPOINT_MAX:g}; "
                                       f"got {ci!r}")
    slowdown = header.setdefault("slowdown", 1.0)
    if not _is_number(slowdown) or not MIN_SLOWDOWN <= slowdown <= MAX_SLOWDOWN:
        raise DataError(path, 1, None, f"header: 'slowdown' must be a number, "
                                       f"{MIN_SLOWDOWN:g}..{MAX_SLOWDOWN:g}; got {slowdown!r}")
    if "interface_text" in header and not isinstance(header["interface_text"], str):
        raise DataError(path, 1, None, "header: 'interface_text' must be a string")
    if "expect" in header and not isinstance(header["expect"], list):
        raise DataError(path, 1, None, "header: 'expect' must be a list")
    return header


def _finite_pair(v) -> bool:
    return isinstance(v, list) and len(v) == 2 and all(
        _is_number(x) and math.isfinite(x) for x in v)


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _check_event(obj: Any) -> str | None:
    """What is wrong with an event line, or None."""
    if not isinstance(obj, dict) or set(obj) != {"step", "event"}:
        return 'expected {"step": N, "event": {...}} or {"end": N, "hash": "..."}'
    step, event = obj["step"], obj["event"]
    if not isinstance(step, int) or isinstance(step, bool) or step < 0:
        return f"'step' must be a whole number >= 0, got {step!r}"
    return event_problem(event)


def event_problem(event: Any) -> str | None:
    """What is wrong with an input event (from a log line or a live source), or None."""
    if not isinstance(event, dict):
        return "'event' must be an object"
    kind = event.get("type")
    if kind not in EVENT_FIELDS:
        return f"unknown event type {kind!r}; expected one of: {', '.join(EVENT_FIELDS)}"
    missing = [f for f in EVENT_FIELDS[kind] if f not in event]
    if missing:
        return f"{kind} event without {', '.join(repr(m) for m in missing)}"
    if kind == "mouse" and not (_is_number(event["x"]) and _is_number(event["y"])):
        return "mouse event: 'x' and 'y' must be numbers"
    if kind == "key" and not (isinstance(event["key"], str) and isinstance(event["down"], bool)):
        return "key event: 'key' must be a string and 'down' true or false"
    if kind == "action":
        if not isinstance(event["name"], str):
            return "action event: 'name' must be a string"
        if event["name"] == "rewind" and not (isinstance(event.get("to_step"), int)
                                              and event["to_step"] >= 0):
            return "rewind action needs a whole-number 'to_step' >= 0"
    if kind == "reload" and not (isinstance(event["text"], str)
                                 and isinstance(event.get("path", ""), str)):
        return "reload event: 'text' (and 'path') must be strings"
    if kind == "gesture" and not (isinstance(event["key"], str) and isinstance(event["path"], list)
                                  and all(isinstance(p, list) and len(p) == 3
                                          and all(_is_number(v) for v in p)
                                          for p in event["path"])):
        return "gesture event: 'key' must be a string and 'path' a list of [t, x, y]"
    if kind == "channels" and not (isinstance(event["values"], dict) and all(
            isinstance(n, str) and _is_number(v) and math.isfinite(v)
            for n, v in event["values"].items())):
        return "channels event: 'values' must map channel names to finite numbers"
    if kind == "push" and not (
            isinstance(event["link"], str) and _finite_pair(event["impulse"])
            and ("point" not in event or _finite_pair(event["point"]))):
        return "push event: 'link' must be a name, 'impulse' (and 'point') [x, y] numbers"
    if kind == "drag" and event["phase"] not in ("start", "move", "end"):
        return f"drag event: unknown phase {event['phase']!r}"
    return None


def _json_problem(exc: json.JSONDecodeError) -> str:
    """json's message with its column: some messages end in "at" ("Unterminated string
    starting at"), which must not become "starting at at column 5"."""
    msg = exc.msg[:-3] if exc.msg.endswith(" at") else exc.msg
    return f"{msg} at column {exc.colno}"


def read_log(path: str | Path, allow_truncated: bool = False) -> Log:
    """Parse a log. A bad line raises DataError(path, line); with ``allow_truncated``
    the valid lines before it are kept (``Log.truncated_at`` says where it stopped)."""
    path_s = str(path)
    try:
        text = Path(path).read_bytes().decode("utf-8", errors="replace")
    except IsADirectoryError:
        raise DataError(path_s, None, None, "is a folder; expected a log (.jsonl) or a log "
                                            "name") from None
    except FileNotFoundError:
        raise DataError(path_s, None, None, "no such file (expected a log (.jsonl) or a log "
                                            "name)") from None
    except OSError as exc:
        raise DataError(path_s, None, None, f"cannot read log: {exc.strerror or exc}") from None
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    elif lines and lines[-1] != "":
        pass  # last line without newline: a killed writer; parsed (and refused) as usual
    if not lines or not lines[0].strip():
        raise DataError(path_s, 1, None, "empty log: line 1 must be a header")
    try:
        header = json.loads(lines[0])
    except ValueError as exc:
        raise DataError(path_s, 1, None, f"not valid JSON ({_json_problem(exc)}); line 1 "
                                         "must be the log header") from None
    log = Log(path_s, _check_header(path_s, header))
    for i, line in enumerate(lines[1:], start=2):
        problem = None
        obj = None
        if log.end is not None:
            problem = "nothing may follow the end line"
        elif not line.strip():
            problem = "empty line"
        else:
            try:
                obj = json.loads(line)
            except ValueError as exc:
                problem = f"not valid JSON ({_json_problem(exc)})"
        if problem is None and isinstance(obj, dict) and "end" in obj:
            end = obj.get("end")
            if (set(obj) - {"end", "hash"} or not isinstance(end, int) or isinstance(end, bool)
                    or end < 0 or not isinstance(obj.get("hash", ""), str)):
                problem = 'bad end line: expected {"end": N, "hash": "..."}'
            else:
                log.end = obj
                continue
        if problem is None:
            problem = _check_event(obj)
        if problem is not None:
            if allow_truncated:
                log.truncated_at = i
                log.truncated_reason = problem
                break
            hint = "" if log.end is not None else " (--allow-truncated replays the lines before it)"
            raise DataError(path_s, i, None, problem + hint)
        log.events.append(LogEvent(obj["step"], obj["event"], i))
    return log


def record_events(session, events, until_step: int, path: str | Path, **header) -> Path:
    """Play scripted ``(step, event)`` pairs into a session while recording a log
    (how test and example logs are made without a window)."""
    from puppet.timeline.playback import play

    with Recorder(session, path, **header) as rec:
        play(session, events, until_step)
    return rec.path
