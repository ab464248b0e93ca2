"""Replay a log through a fresh Session: same events at the same steps, same bits.

The header names the interface, character and scene; when one of those files has
changed since the recording (its hash differs) the replay warns in one line and goes
on. Events are applied in file order; the sim is advanced to each event's step first.

This is the replay engine (``replay``, ``ReplayResult``, ``LogFeeder``,
``setup_for_log``, ``new_session``, ``apply_log``, ``find_log``); the sampled run it
records is ``puppet.timeline.trajectory`` (``Sampler``, ``Trajectory``); what the
``puppet replay`` command prints and exits with is ``puppet.timeline.report``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from puppet import __version__
from puppet.data.catalog import Folders, Setup, file_hash, find, load_setup, setup_from_text
from puppet.data.errors import DataError
from puppet.session import Session
from puppet.session.playback import next_move, play, ticks
from puppet.session.stepping import feed
from puppet.timeline.log import Log, embedded_problem, read_log
from puppet.timeline.quoting import reload_error, unquoted_error
from puppet.timeline.trajectory import Sampler, Trajectory
from puppet.timeline.trajectory import sample_every as _sample_every

if TYPE_CHECKING:  # the expectations are imported only by a checked replay
    from puppet.timeline.expectations import Outcome

@dataclass
class ReplayResult:
    """What a replay ended in. ``failed`` lists the expectations that did not hold
    (including the recorded end hash, when the log has one and the replay ran to
    the end)."""

    path: str
    final_hash: str
    steps: int
    time: float
    recorded_hash: str | None
    trajectory: Trajectory | None
    outcomes: list[Outcome] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    truncated_at: int | None = None
    session: Session | None = field(default=None, repr=False)
    # True/False: the replay ended in the recorded end state or not; None: nothing to
    # compare (no end line, stopped early with until_step, or a truncated log)
    same_end: bool | None = None
    blowups: list[str] = field(default_factory=list)  # the session's note for each
    # checks a checked replay could not make (a cut log's end state), one line each
    unchecked: list[str] = field(default_factory=list)

    def __post_init__(self):
        for o in self.outcomes:  # the check a closed log's end line adds
            if o.expectation == SAME_END and not o.kind:
                o.kind = "same_end"

    def __repr__(self) -> str:
        verdict = "ok" if self.ok else f"{len(self.failed)} of {len(self.outcomes)} failed"
        return (f"ReplayResult(path={self.path!r}, steps={self.steps}, "
                f"hash={self.final_hash!r}, {verdict})")

    @property
    def failed(self) -> list[Outcome]:
        return [o for o in self.outcomes if not o.passed]

    @property
    def ok(self) -> bool:
        return not self.failed

    @property
    def summary(self) -> dict:
        return {"log": self.path, "steps": self.steps, "time": round(self.time, 6),
                "hash": self.final_hash, "recorded_hash": self.recorded_hash,
                "same_end": self.same_end,
                "checks": len(self.outcomes), "failed": [str(o) for o in self.failed],
                "warnings": list(self.warnings), "truncated_at": self.truncated_at,
                "blowups": list(self.blowups), "unchecked": list(self.unchecked)}


def find_log(name: str) -> str:
    """A LOG argument as a path: an existing file or a path as given; a bare name is
    looked up as interfaces and scripts are, in assets/logs/ and then recordings/
    (where the window saves its sessions). DataError names the known logs."""
    if Path(name).is_file() or len(Path(name).parts) > 1:
        return name
    try:
        return str(find("log", name))
    except DataError as exc:
        try:
            return str(find("recording", name))
        except DataError:
            raise exc from None


SAME_END = "same end as the recording"  # the check a closed log's end line gives


def _checking(log: Log) -> str:
    """How a checked replay of a cut log says what it checks: the events it has."""
    return (f"checking the expectations on its {len(log.events)} events only (to step "
            f"{log.last_step}); '{SAME_END}' is not checked")


def cut_warnings(log: Log, check: bool = False, for_check: bool = False) -> list[str]:
    """What a replay should say about a log that does not end as a closed recording
    does: cut off at a bad line (replayed with --allow-truncated), or with no end line
    (the recording was killed or crashed: nothing to compare the end state with).
    ``check``: the replay evaluates expectations (on what the log has, see ``require_end``).
    ``for_check``: the words of ``puppet check`` (which reads the log, never cut, and
    does not replay it) about a log with no end line: what a replay would do with it."""
    if log.truncated_at is not None:
        what = (_checking(log) if check
                else f"replaying the {len(log.events)} events before it")
        return [f"{log.path}:{log.truncated_at}: warning: {log.truncated_reason}; {what}"]
    if log.end is None:
        what = (_checking(log) if check
                else f"puppet replay plays its {len(log.events)} events with no recorded "
                     "end state to compare, and replay --check refuses it" if for_check
                else f"replaying its {len(log.events)} events, with no recorded end state "
                     "to compare")
        return [f"{log.path}: warning: no end line (the recording did not close: killed or "
                f"crashed?); {what}"]
    return []


# how ``puppet check`` says what a log cut mid-line needs (read_log's TRUNCATED_HINT is
# an option of the replay it was run in)
CHECK_TRUNCATED_HINT = " (puppet replay --allow-truncated replays the lines before it)"


def require_end(log: Log, allow_truncated: bool, for_check: bool = False) -> None:
    """The rule of a checked replay (``puppet replay --check``, ``replay(check=True)``,
    ``puppet.testing.replay_log``, ``--video --check``): a log without its end line is
    refused as a log cut mid-line is, unless ``allow_truncated``. Without the end line
    the replay stops at the last event instead of where the recording stopped, so
    expectations at the end would be measured at another time, and the end state cannot
    be compared. A plain replay (the window's, or headless without --check) goes on
    with the warning of ``cut_warnings``. The error names the log's last line (the end
    line would follow it); ``for_check``: ``puppet check``'s refusal, whose hint names
    the replay command to run."""
    if log.end is not None or log.truncated_at is not None or allow_truncated:
        return
    last = log.events[-1].line if log.events else 1
    what = (f"on its {len(log.events)} events, to step {log.last_step}," if log.events
            else "at step 0 (it has no events),")
    option = "puppet replay --headless --check --allow-truncated" if for_check \
        else "--allow-truncated"
    raise DataError(log.path, last, None,
                    'no end line ({"end": N, "hash": "..."}) after this last line: the '
                    "recording did not close (killed or crashed?) or the file was cut, so "
                    "where the run ended and its end state are unknown and the checks "
                    f"cannot be made ({option} checks the expectations {what} "
                    "without the end state)")


def not_checked(log: Log, until_step: int | None = None) -> list[str]:
    """What a checked replay of this log leaves out, one line each (printed with the
    checks): the end state, when the log has none to compare with."""
    if until_step is not None:
        return []  # stopped early by request: nothing to compare at that step
    if log.truncated_at is not None:
        why = f"the log was cut at line {log.truncated_at}"
    elif log.end is None:
        why = "the log has no end line"
    elif not log.end_hash:
        why = "the end line has no hash"
    else:
        return []
    return [f"{SAME_END} ({why}; the checks above cover its {len(log.events)} events, "
            f"to step {log.last_step})"]


def copy_note(log: Log, refused: bool) -> str:
    """The note of a replay (and of ``puppet check``) that plays the interface copy the
    header keeps because the file it names is not read: not found, or (``refused``) a
    path outside the catalog and the log's folder, which a log may not make puppet read."""
    name = log.header["interface"]
    why = ("is outside the catalog and the log's folder, so it is not read (a log "
           "reads no other files)" if refused
           else "is not found (in the catalog or the log's folder)")
    return f"{log.path}: note: interface file '{name}' {why}; the copy recorded in the log plays"


def differs_warning(log: Log, kind: str, path: Path, found: str | None,
                    has_copy: bool) -> str:
    """The one words (replay and ``puppet check`` alike) for a file the header names
    whose content is not the one recorded: ``path`` is the file the name found now
    (today's version, or a variant of that name in the log's folder), ``found`` its
    hash (None: not shown, a file beside the log: its hash would tell of its content);
    ``has_copy``: the header keeps the recorded interface."""
    name = log.header.get(kind, str(path))
    shown = f"{path}, hash {found}" if found is not None else str(path)
    return (f"{log.path}: warning: {kind} '{name}': the file found ({shown}) "
            f"differs from the one recorded (hash {log.header.get(f'{kind}_hash')}); the "
            "replay may end elsewhere"
            + (" (puppet replay --as-recorded replays the recorded interface)" if has_copy
               else ""))


def setup_for_log(log: Log, as_recorded: bool = False,
                  for_check: bool = False) -> tuple[Setup, list[str]]:
    """Load what the header names; a one-line warning for each file that changed
    (``for_check``: in the words of ``puppet check``, which does not replay).

    The interface is today's file, so that yesterday's session replays against
    today's interface (a designer's test; a feat log fails when its interface breaks),
    with a warning if it changed. ``as_recorded`` replays the copy the header holds
    (``interface_text``) instead: the session exactly as it was played; so does a log
    whose interface file is gone."""
    h = log.header
    embedded = h.get("interface_text")
    as_recorded_option = "puppet replay --as-recorded" if for_check else "--as-recorded"
    if as_recorded and embedded is None:
        raise DataError(log.path, 1, None, "header: no recorded copy of the interface "
                                           "(interface_text) to replay --as-recorded")
    within = Folders((Path(log.path).resolve().parent,))  # the catalog, or beside the log
    refused = False  # the header names a file outside the catalog and the log's folder
    try:
        where = find("interface", h["interface"], within)
    except DataError as exc:
        where = None
        refused = exc.message.endswith("it was not read")
        if embedded is None:
            raise DataError(log.path, 1, None, f"header: {exc.message}") from None
    from_copy = embedded is not None and (as_recorded or where is None)
    try:
        if from_copy:
            setup = setup_from_text(embedded, where or Path(h["interface"]), h["scene"],
                                    within)
        else:
            setup = load_setup(str(where), h["scene"], within)
    except DataError as exc:
        if exc.line is None and exc.path in (h["interface"], h["scene"]):  # not found
            raise DataError(log.path, 1, None, f"header: {exc.message}") from None
        hint = (f" ({as_recorded_option} replays the log's own copy of the interface)"
                if not from_copy and embedded is not None and exc.path == str(where) else "")
        if within.found:
            raise unquoted_error(log, within.found, hint) from None
        if hint:
            raise DataError(exc.path, exc.line, exc.col, exc.message + hint) from None
        raise
    warnings = []
    if h.get("puppet") != __version__:
        warnings.append(f"{log.path}: warning: recorded by puppet {h.get('puppet')}, this is "
                        f"{__version__}: the physics or the interface runtime may have "
                        f"changed since, so the replay may end elsewhere")
    reloads = [e.step for e in log.events if e.event["type"] == "reload"]
    if reloads and not from_copy:
        warnings.append(f"{log.path}: note: the session hot-reloaded its interface (first at "
                        f"step {reloads[0]}); from there on the recorded versions play")
    if from_copy and not as_recorded:
        warnings.append(copy_note(log, refused))
    edited = embedded_problem(h) if (from_copy or for_check) else None
    if edited:
        warnings.append(f"{log.path}: warning: {edited}; "
                        + ("a replay of the copy (puppet replay --as-recorded) plays it"
                           if not from_copy else "playing it, not the session recorded"))
    for kind, path in (("interface", setup.interface_path), ("character", setup.character_path),
                       ("scene", setup.scene_path)):
        if kind == "interface" and from_copy:
            continue  # replayed from the header's copy
        recorded = h.get(f"{kind}_hash")
        if recorded is not None and (found := file_hash(Path(path))) != recorded:
            warnings.append(differs_warning(
                log, kind, Path(path), None if Path(path).resolve() in within.found else found,
                kind == "interface" and embedded is not None))
    if h.get("character") and Path(str(h["character"])).stem != Path(setup.character_path).stem:
        warnings.append(f"{log.path}: warning: recorded with character '{h['character']}', "
                        f"the interface now uses '{Path(setup.character_path).stem}'")
    return setup, warnings


def new_session(log: Log, setup: Setup) -> Session:
    return Session(setup, dt=float(log.header["dt"]),
                   checkpoint_interval=float(log.header["checkpoint_interval"]))


def apply_log(session: Session, log: Log, until_step: int | None = None, every: int = 0,
              on_tick=None) -> None:
    """Feed a log's events into a session (file order); DataError at a bad event's line."""
    current = {"i": -1}

    def on_event(i, _event):
        current["i"] = i

    try:
        play(session, log.pairs(), until_step, every, on_tick, end_step=log.last_step,
             on_event=on_event)
    except DataError as exc:  # a reload event whose interface text is invalid
        i = current["i"]
        line = log.events[i].line if 0 <= i < len(log.events) else None
        raise reload_error(log, line, session.setup, exc) from None
    except (ValueError, KeyError, TypeError) as exc:
        i = current["i"]
        line = log.events[i].line if 0 <= i < len(log.events) else None
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        raise DataError(log.path, line, None, f"cannot apply this event: {msg}") from None


def replay(path: str | Path | Log, until_step: int | None = None, allow_truncated: bool = False,
           check: bool = True, sample_every: int | None = None,
           trajectory: bool = True, as_recorded: bool = False,
           adjust=None, expect: list | None = None,
           frames: tuple[int, Callable[[Session], None]] | None = None,
           physics=None) -> ReplayResult:
    """Replay a log (a path, or one already read) headless, as fast as it goes;
    evaluate its expectations (``check``; a log without its end line is then refused
    unless ``allow_truncated``: ``require_end``). ``expect``: expectation dicts to check
    instead of the log's (a test's; no end-state check is added), under the same rule.
    ``as_recorded``: see ``setup_for_log``. ``adjust``: a function of the Setup
    returning the one to replay on instead (a test's weaker servos). ``physics``: an
    ``OtherPhysics`` (other solver passes, slop or step: ``puppet replay
    --solver-passes/--step``): the log replayed on it, its end state not compared.
    ``frames``: (every, on_frame), on_frame called with the session every ``every``
    steps (the images of ``puppet replay --frames``; reading the session only, they
    leave the replay as it is)."""
    log = path if isinstance(path, Log) else read_log(path, allow_truncated)
    path = log.path
    if physics:
        log = physics.log(log)
        adjust = physics.adjust if adjust is None else (
            lambda setup, first=adjust: physics.adjust(first(setup)))
    check = check or expect is not None
    if check:  # before anything is loaded: the log itself cannot be checked
        require_end(log, allow_truncated)
    setup, warnings = setup_for_log(log, as_recorded)
    if adjust is not None:
        setup = adjust(setup)
    warnings += cut_warnings(log, check)
    expectations = None
    if check:  # a plain replay does not import numpy or the expectations (process start)
        from puppet.timeline.expectations import (
            Outcome,
            evaluate_all,
            load_expectations,
            parse_expectations,
        )

        expectations = (load_expectations(path, log.header) if expect is None
                        else parse_expectations(expect, f"{path} (expect=)"))
    session = new_session(log, setup)
    if expectations is not None:
        expectations.check_links(list(session.character.link_order))
    sampler = (Sampler(session, touches=expectations is not None and expectations.touches)
               if (trajectory or expectations) else None)
    if sampler is not None:
        sampler(session)
    if sample_every is None:  # the trajectory at 120 Hz on the replay's step
        sample_every = _sample_every(session.sim.dt)
    every, on_tick = ticks((sample_every if sampler else 0, sampler), frames or (0, None))
    apply_log(session, log, until_step, every, on_tick)
    if sampler is not None and (not sampler.rows or sampler.rows[-1][0] != session.steps):
        sampler(session)
    traj = sampler.trajectory() if sampler is not None else None
    final = session.sim.state_hash()
    same_end = None
    if log.end_hash and until_step is None and log.truncated_at is None and not physics:
        same_end = final == log.end_hash
    outcomes: list[Outcome] = []
    if expectations is not None:
        outcomes = evaluate_all(expectations.items, traj, final)
        if same_end is not None and expect is None:
            outcomes.append(Outcome(SAME_END, same_end,
                                    f"replayed {final}, recorded {log.end_hash}",
                                    margin=0.0 if same_end else float("-inf")))
    return ReplayResult(str(path), final, session.steps, session.time, log.end_hash, traj,
                        outcomes, warnings, log.truncated_at, session, same_end,
                        list(session.blowup_messages),
                        not_checked(log, until_step) if check and expect is None else [])


class LogFeeder:
    """Feeds a log into a session a budget of steps at a time (the window's replay,
    the video export, the ghost): ``play``'s rule (``next_move``), cut into frames.

    ``on_action`` (if given) gets every app action the replayed events ask for (e.g.
    SetSlowdown(4)), for the viewer's clock to follow as it did live (``SimClock.apply``).
    """

    def __init__(self, session: Session, log: Log, until_step: int | None = None,
                 on_action: Callable[[str], object] | None = None):
        self.session = session
        self.events = log.pairs()
        self.i = 0
        self.until = until_step
        self.end = log.last_step
        self.on_action = on_action

    def _move(self) -> int | None:
        nxt = self.events[self.i][0] if self.i < len(self.events) else None
        return next_move(self.session.steps, nxt, self.until, self.end)

    @property
    def finished(self) -> bool:
        return self._move() is None

    def advance(self, steps: int) -> None:
        """Run up to ``steps`` steps; the events due at the step reached act too (in
        one call of the session's stepping loop: a replay's hot path, an event every
        frame, a frame a few steps)."""
        self.i = feed(self.session, self.events, self.i, self.until, self.end, steps,
                      on_action=None if self.on_action is None else self._acted,
                      on_raise=self._raised)[0]

    def _raised(self, i: int) -> None:
        """The call ended by an exception: the events before ``i`` were taken (else
        ``i`` would lag and the next ``advance`` apply them again)."""
        self.i = i

    def _acted(self, i: int, action) -> None:
        """An app action an event asked for: ``i`` is the next event's index then (the
        callback may read it: the playtest's slowdown in force)."""
        self.i = i
        self.on_action(action)
