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

Events are in step order: each event's step is at least the one before it, except
after an event that moves the session back in time (a rewind goes to its ``to_step``;
a restore, a take, or a press of the restore key go where the history says; while
the window's scrub key is held the events go to the steps shown): ``_StepOrder``.
Events replay in file order. The file is written as the session
goes and flushed after every line, so a killed process keeps all of it. Hashes are
16 hex digits; the header's ``interface_text`` is the file whose ``interface_hash``
it carries (a replay that plays an edited copy warns: ``embedded_problem``).
"""

from __future__ import annotations

import datetime
import json
import math
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from puppet import __version__
from puppet.data import ranges
from puppet.data.catalog import FOLDERS, ROOT, Setup
from puppet.data.errors import DataError
from puppet.data.interfaces import (
    CHECKPOINT_EVERY,
    CHECKPOINT_MAX,
    CHECKPOINT_MIN,
    MAX_SLOWDOWN,
    MIN_SLOWDOWN,
)
from puppet.data.keys import APP_KEYS, normalize_key
from puppet.interface.event_checks import MAX_PATH, event_problem, is_number, short
from puppet.interface.events import Event

FORMAT = "puppet-log"
VERSION = 1
RECORDINGS = FOLDERS["recording"][0]  # where (under the root) the window records to



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


HASH = re.compile(r"[0-9a-f]{16}")  # how a log writes a hash (file or state): 16 hex digits
EMBEDDED = {"interface_text": "interface_hash"}  # a file's text the header keeps -> its hash


def text_hash(raw: bytes) -> str:
    """The hash a log writes for a file's bytes (``catalog.file_hash`` of the file):
    the first 16 hex digits of its SHA-256; ``embedded_problem`` checks a kept text
    against it."""
    import hashlib  # here: OpenSSL's start-up is ~5 ms that a check does not need

    return hashlib.sha256(raw).hexdigest()[:16]


def embedded_problem(header: dict) -> str | None:
    """What is wrong with the file texts a header keeps (``EMBEDDED``), or None: each
    should be the file whose hash the header names. One that is not was edited (or
    damaged) after the recording: a replay that plays it (``--as-recorded``, or the
    file gone) warns, since it plays a session other than the one recorded - on purpose
    in a test that weakens a log's interface to see it fail, so not refused. A
    recording made before the text was kept byte for byte read it with universal
    newlines, so the text with CRLF line ends counts as the file too."""
    for text_key, hash_key in EMBEDDED.items():
        text, recorded = header.get(text_key), header.get(hash_key)
        if not isinstance(text, str) or not isinstance(recorded, str):
            continue
        raw = text.encode("utf-8", errors="surrogatepass")
        if recorded not in (text_hash(raw), text_hash(raw.replace(b"\n", b"\r\n"))):
            return (f"the header's '{text_key}' (hash {text_hash(raw)}) is not the file "
                    f"recorded ('{hash_key}' {recorded}): the copy was edited after the "
                    "recording")
    return None


def make_header(session, slowdown: float | None = None, description: str | None = None,
                expect: list | None = None, script: tuple[str, str] | None = None) -> dict:
    """The header of a log. It keeps the interface file's text (``interface_text``),
    so the log can replay the interface as recorded (``--as-recorded``), and from
    anywhere once the file is moved or deleted (a hot reload edits it while recording).
    ``script``: (name, text) of a reactive script that played the session: a replay
    does not need it (the events it made are in the log), a playtest plays it again."""
    setup: Setup = session.setup
    raw = Path(setup.interface_path).read_bytes()  # the text kept and its hash: one read
    header: dict[str, Any] = {
        "format": FORMAT,
        "version": VERSION,
        "puppet": __version__,
        "interface": _name(setup.interface_path, "interface"),
        "interface_hash": text_hash(raw),
        "character": _name(setup.character_path, "character"),
        "character_hash": text_hash(Path(setup.character_path).read_bytes()),
        "scene": _name(setup.scene_path, "scene"),
        "scene_hash": text_hash(Path(setup.scene_path).read_bytes()),
        "dt": session.sim.dt,
        "seed": 0,  # nothing is random yet; kept so that logs stay readable if it is
        "slowdown": float(slowdown if slowdown is not None else setup.interface.slowdown),
        "checkpoint_interval": session.checkpoint_interval,
    }
    header["interface_text"] = raw.decode("utf-8")  # (its line ends as in the file)
    if description:
        header["description"] = description
    if expect:
        header["expect"] = list(expect)
    if script is not None:
        header["script"], header["script_text"] = script
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
                 description: str | None = None, expect: list | None = None,
                 script: tuple[str, str] | None = None):
        self.session = session
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        try:
            self.file = self.path.open("x", encoding="utf-8")
        except FileExistsError:
            raise DataError(str(path), None, None, EXISTS) from None
        self._write(make_header(session, slowdown, description, expect, script))
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


DT_MIN, DT_MAX = 1.0e-5, 0.05  # s: a log's simulation step (puppet's is 1/480 s)
MAX_SECONDS = 24 * 3600.0  # s of simulated time a log may reach (its steps are bounded)
MAX_LOG_BYTES = 256 << 20  # a log file's largest size (30 minutes of mouse are ~10 MB)
MAX_LINE = 8_000_000  # characters in one line (an embedded interface is at most 2 MB)
# how a refused cut log (a bad line, or under --check no end line) says what to do
TRUNCATED_HINT = " (--allow-truncated replays the lines before it)"


def max_step(dt: float) -> int:
    """The last step a log with this ``dt`` may name."""
    return int(MAX_SECONDS / dt)


def _check_header(path: str, header: Any) -> dict:
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise DataError(path, 1, None, "not a puppet log: line 1 must be a header with "
                                       f'"format": "{FORMAT}"')
    version = header.get("version")
    if version != VERSION:
        shown = repr(version) if len(repr(version)) <= 40 else repr(version)[:37] + "..."
        raise DataError(path, 1, None, f"log format version {shown} is not supported: "
                                       f"this puppet ({__version__}) reads version {VERSION}")
    for key, kind in (("interface", str), ("scene", str), ("dt", (int, float))):
        if not isinstance(header.get(key), kind) or isinstance(header.get(key), bool):
            raise DataError(path, 1, None, f"header: '{key}' is missing or not a "
                                           f"{'number' if key == 'dt' else 'string'}")
    for key in ("interface", "scene", "character"):
        value = header.get(key)
        if key in header and not (isinstance(value, str) and 0 < len(value) <= MAX_PATH):
            raise DataError(path, 1, None, f"header: '{key}' must be a name or path of "
                                           f"1..{MAX_PATH} characters")
    if not DT_MIN <= header["dt"] <= DT_MAX:
        raise DataError(path, 1, None, f"header: 'dt' must be a finite number in "
                                       f"{ranges.fmt(DT_MIN)}..{ranges.fmt(DT_MAX)} s, "
                                       f"got {header['dt']!r}")
    ci = header.setdefault("checkpoint_interval", CHECKPOINT_EVERY)
    if not is_number(ci) or not CHECKPOINT_MIN <= ci <= CHECKPOINT_MAX:
        raise DataError(path, 1, None, f"header: 'checkpoint_interval' must be a number of "
                                       f"seconds, {CHECKPOINT_MIN:g}..{CHECKPOINT_MAX:g}; "
                                       f"got {ci!r}")
    slowdown = header.setdefault("slowdown", 1.0)
    if not is_number(slowdown) or not MIN_SLOWDOWN <= slowdown <= MAX_SLOWDOWN:
        raise DataError(path, 1, None, f"header: 'slowdown' must be a number, "
                                       f"{MIN_SLOWDOWN:g}..{MAX_SLOWDOWN:g}; got {slowdown!r}")
    if "interface_text" in header and not isinstance(header["interface_text"], str):
        raise DataError(path, 1, None, "header: 'interface_text' must be a string")
    if "expect" in header and not isinstance(header["expect"], list):
        raise DataError(path, 1, None, "header: 'expect' must be a list")
    for key in ("description", "puppet", "interface_hash", "character_hash", "scene_hash",
                "script", "script_text"):
        if key in header and not isinstance(header[key], str):
            raise DataError(path, 1, None, f"header: '{key}' must be a string")
    for key in ("interface_hash", "character_hash", "scene_hash"):
        if key in header and not HASH.fullmatch(header[key]):
            raise DataError(path, 1, None, f"header: '{key}' must be a hash of 16 hex digits "
                                           f"(0-9, a-f), got {short(header[key])}")
    return header


def _check_event(obj: Any, last_step: int) -> str | None:
    """What is wrong with an event line, or None."""
    if not isinstance(obj, dict) or set(obj) != {"step", "event"}:
        return 'expected {"step": N, "event": {...}} or {"end": N, "hash": "..."}'
    step, event = obj["step"], obj["event"]
    if not isinstance(step, int) or isinstance(step, bool) or not 0 <= step <= last_step:
        return (f"'step' must be a whole number 0..{last_step} ({MAX_SECONDS / 3600:g} h at "
                f"this log's dt), got {short(step)}")
    return event_problem(event, last_step)


def _json_problem(exc: ValueError) -> str:
    """json's message with its column: some messages end in "at" ("Unterminated string
    starting at"), which must not become "starting at at column 5"."""
    if not isinstance(exc, json.JSONDecodeError):
        return " ".join(str(exc).split())
    msg = exc.msg[:-3] if exc.msg.endswith(" at") else exc.msg
    return f"{msg} at column {exc.colno}"


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number a log may hold (numbers are finite)")


def _finite(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"{text[:20]} is too large a number (numbers are finite)")
    return value


def _loads(line: str):
    """json.loads, refusing NaN, Infinity and numbers that overflow to them; any
    problem is a ValueError whose message says what (RecursionError included)."""
    if len(line) > MAX_LINE:
        raise ValueError(f"line too long ({len(line)} characters; at most {MAX_LINE})")
    try:
        return json.loads(line, parse_constant=_no_constant, parse_float=_finite)
    except RecursionError:
        raise ValueError("nested too deeply") from None


def read_log(path: str | Path, allow_truncated: bool = False) -> Log:
    """Parse a log. A bad line raises DataError(path, line); with ``allow_truncated``
    the valid lines before it are kept (``Log.truncated_at`` says where it stopped)."""
    path_s = str(path)
    try:
        with Path(path).open("rb") as fh:
            if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
                raise DataError(path_s, None, None, "not a regular file")
            raw = fh.read(MAX_LOG_BYTES + 1)
    except IsADirectoryError:
        raise DataError(path_s, None, None, "is a folder; expected a log (.jsonl) or a log "
                                            "name") from None
    except FileNotFoundError:
        raise DataError(path_s, None, None, "no such file (expected a log (.jsonl) or a log "
                                            "name)") from None
    except OSError as exc:
        raise DataError(path_s, None, None, f"cannot read log: {exc.strerror or exc}") from None
    if len(raw) > MAX_LOG_BYTES:
        raise DataError(path_s, None, None, f"log too large (over {MAX_LOG_BYTES} bytes)")
    text = raw.decode("utf-8", errors="replace")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    elif lines and lines[-1] != "":
        pass  # last line without newline: a killed writer; parsed (and refused) as usual
    if not lines or not lines[0].strip():
        raise DataError(path_s, 1, None, "empty log: line 1 must be a header")
    try:
        header = _loads(lines[0])
    except ValueError as exc:
        raise DataError(path_s, 1, None, f"not valid JSON ({_json_problem(exc)}); line 1 "
                                         "must be the log header") from None
    log = Log(path_s, _check_header(path_s, header))
    last_step = max_step(log.header["dt"])
    order = _StepOrder(log.header.get("interface_text"))
    for i, line in enumerate(lines[1:], start=2):
        problem = None
        obj = None
        if log.end is not None:
            problem = "nothing may follow the end line"
        elif not line.strip():
            problem = "empty line"
        else:
            try:
                obj = _loads(line)
            except ValueError as exc:
                problem = f"not valid JSON ({_json_problem(exc)})"
        if problem is None and isinstance(obj, dict) and "end" in obj:
            end = obj.get("end")
            if (set(obj) - {"end", "hash"} or not isinstance(end, int) or isinstance(end, bool)
                    or not 0 <= end <= last_step or not isinstance(obj.get("hash", ""), str)):
                problem = (f'bad end line: expected {{"end": N, "hash": "..."}}, N in '
                           f'0..{last_step}')
            elif "hash" in obj and not HASH.fullmatch(obj["hash"]):
                problem = (f"bad end line: 'hash' must be a state hash of 16 hex digits "
                           f"(0-9, a-f), got {short(obj['hash'])}")
            else:
                log.end = obj
                continue
        if problem is None:
            problem = _check_event(obj, last_step) or order.problem(obj)
        if problem is not None:
            if allow_truncated:
                log.truncated_at = i
                log.truncated_reason = problem
                break
            hint = "" if log.end is not None else TRUNCATED_HINT
            raise DataError(path_s, i, None, problem + hint)
        log.events.append(LogEvent(obj["step"], obj["event"], i))
        order.after(obj, i)
    return log


RESTORE_KEY = APP_KEYS["restore"][0]  # the app's key back to the last checkpoint
SCRUB_KEYS = (APP_KEYS["rewind"][0], APP_KEYS["forward"][0])  # held: the time line moves


class _StepOrder:
    """The rule that a log's events are in step order (an event moved or edited out of
    place replays at another step, so the run ends elsewhere with nothing said).

    An event's step is at least the one before it; after a rewind, at least its
    ``to_step``. Time may go back with nothing in the log saying where to: after a
    restore, a take or a press of the restore key any step may follow, and while a
    scrub key is held (the window's rewind and forward keys: the events go to the
    steps shown, and a rewind action commits the scrub when it is let go) the steps
    are not checked. Those are the app's keys; once an interface text of the log
    rebinds them (``app_keys``), or with no text to say, any key may be one."""

    def __init__(self, interface_text: str | None):
        self.floor = 0  # the least step the next event may have
        self.line: int | None = None  # the line that set it
        self.rewind = False  # set by a rewind (to its to_step)
        self.scrubbing: set[str] = set()  # scrub keys held
        self.rebound = interface_text is None or "app_keys" in interface_text

    def problem(self, obj: dict) -> str | None:
        step = obj["step"]
        if step >= self.floor or self.scrubbing:
            return None
        where = (f"step {self.floor}, where the rewind of line {self.line} went" if self.rewind
                 else f"step {self.floor} of line {self.line}")
        return (f"step {step} comes before {where}; a log's events are in step order "
                "(the log was edited or damaged)")

    def after(self, obj: dict, line: int) -> None:
        event = obj["event"]
        kind, name = event["type"], event.get("name")
        self.line, self.rewind, self.floor = line, False, obj["step"]
        if kind == "reload" and "app_keys" in event["text"]:
            self.rebound = True
        if kind == "action" and name == "rewind":
            self.floor, self.rewind = event["to_step"], True
            self.scrubbing.clear()  # (the commit of a scrub)
        elif kind == "action" and name in ("restore", "take"):
            self.floor = 0
        elif kind == "key":
            key = normalize_key(event["key"])
            if not event["down"]:
                self.scrubbing.discard(key)
            else:
                if self.rebound or key in SCRUB_KEYS:
                    self.scrubbing.add(key)
                if self.rebound or key == RESTORE_KEY:
                    self.floor = 0


def record_events(session, events, until_step: int, path: str | Path, **header) -> Path:
    """Play scripted ``(step, event)`` pairs into a session while recording a log
    (how test and example logs are made without a window)."""
    from puppet.session.playback import play

    with Recorder(session, path, **header) as rec:
        play(session, events, until_step)
    return rec.path
