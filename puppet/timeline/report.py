"""The ``puppet replay`` command's report: what it prints and exits with.

The replay itself is ``puppet.timeline.replay`` (the engine) and the command is
``puppet.commands.replay``; here are one headless replay as a plain dict
(``replay_one``, run in worker processes), each log's state line and checks, the
many-log table and summary line, the verdict words and the exit codes, and the line
the window and a video show when a replay ends (``finished_message``).
"""

from __future__ import annotations

from puppet.data.errors import DataError
from puppet.session import Session
from puppet.timeline.log import Log, read_log
from puppet.timeline.replay import find_log, replay

EXIT_FAILED, EXIT_DATA_ERROR, EXIT_BLOWUP = 1, 2, 3


def replay_one(path: str, until_step: int | None, allow_truncated: bool, check: bool,
                as_recorded: bool = False, physics=None) -> dict:
    """One headless replay, as a plain dict (runs in a worker process). ``path`` may
    be a log's name (``find_log``); ``physics``: an ``OtherPhysics`` to replay on."""
    try:
        log = read_log(find_log(path), allow_truncated)
        result = replay(log, until_step, allow_truncated, check=check, trajectory=check,
                        as_recorded=as_recorded, physics=physics)
    except DataError as exc:
        return {"log": path, "error": str(exc)}
    except Exception as exc:  # noqa: BLE001 - one bad log must not stop the others
        return {"log": path, "error": f"{path}: internal error: {type(exc).__name__}: {exc}"}
    out = result.summary
    out["outcomes"] = [str(o) for o in result.outcomes]
    note = until_note(log, until_step)
    if note:
        out["warnings"].append(note)
    return out


def until_note(log: Log, until_step: int | None) -> str | None:
    """The line to say when ``--until-step`` is past the log's end: the replay goes on
    simulating, with no input, to the step asked (the character settling, falling or
    lying still: a user may want that, so it is not refused, but it is not the log)."""
    if until_step is None or until_step <= log.last_step:
        return None
    dt = log.header.get("dt")
    dt = dt if isinstance(dt, float) and dt > 0 else None

    def at(step: int) -> str:
        return f"step {step}" + (f" ({step * dt:.3f} s)" if dt else "")

    return (f"{log.path}: note: the log ends at {at(log.last_step)}; --until-step "
            f"{until_step} runs on without input to {at(until_step)}")


def verdict(res: dict) -> str:
    """A replay's one word, the same in the table, the summary line and the exit code:
    ERROR (cannot be replayed), FAIL (an expectation failed; with --check the recorded
    end state is one), "differs" (no --check, and the replay did not end in the recorded
    state: not ok either), else ok."""
    if "error" in res:
        return "ERROR"
    if res["failed"]:
        return "FAIL"
    return "differs" if res["same_end"] is False else "ok"


def exit_code(verdicts: list[str], blew_up: bool = False) -> int:
    """2 if a log cannot be replayed, 3 if one blew up (or left the world), 1 if one
    failed or differs, else 0."""
    if "ERROR" in verdicts:
        return EXIT_DATA_ERROR
    if blew_up:
        return EXIT_BLOWUP
    return EXIT_FAILED if {"FAIL", "differs"} & set(verdicts) else 0


def state_line(res: dict) -> str:
    """``LOG: step N  t=...s  state=HASH (same as recorded)  blow-ups=K``."""
    same = {None: "", True: " (same as recorded)",
            False: f" (recorded {res['recorded_hash']}: DIFFERENT)"}[res["same_end"]]
    blown = f"  blow-ups={len(res['blowups'])}" if res["blowups"] else ""
    return (f"{res['log']}: step {res['steps']}  t={res['time']:.3f}s  "
            f"state={res['hash']}{same}{blown}")


def print_notes(res: dict) -> None:
    """A replay's warnings and one line per blow-up, to stderr."""
    import sys

    for w in res.get("warnings", []):
        print(w, file=sys.stderr)
    from puppet.timeline.blowups import fold

    for note in fold(res.get("blowups", [])):
        print(f"{res['log']}: {note}", file=sys.stderr)


def finished_message(session: Session, log: Log) -> str:
    """What the window and a video say when a replay ends: where, and whether the state
    is the recorded one."""
    final, recorded = session.sim.state_hash(), log.end_hash
    same = ("no recorded end state to compare" if recorded is None
            else "the same as recorded" if final == recorded
            else f"recorded {recorded}: DIFFERENT")
    return f"replay finished at step {session.steps}: state {final} ({same})"


def print_one(res: dict, check: bool) -> None:
    print(state_line(res))
    if check:
        for line in res["outcomes"]:
            print(f"  {line}")
        if not res["outcomes"]:
            print("  (no expectations)")
        for line in res.get("unchecked", []):
            print(f"  not checked: {line}")
    print_notes(res)


def results_table(results: list[dict], check: bool) -> str:
    rows = [("log", "steps", "state", "checks", "result")]
    for r in results:
        if "error" in r:
            rows.append((r["log"], "-", "-", "-", "ERROR"))
            continue
        n, failed = r["checks"], len(r["failed"])
        rows.append((r["log"], str(r["steps"]), r["hash"],
                     f"{n - failed}/{n}" if check else "-", verdict(r)))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip()
                     for row in rows)


def summary_line(results: list[dict], check: bool) -> str:
    """``N logs: A ok, B failed, C errors, D blow-ups`` (without --check, a log that
    does not end in its recorded state is counted as "differ", not ok)."""
    words = [verdict(r) for r in results]
    middle = (f"{words.count('FAIL')} failed" if check else f"{words.count('differs')} differ")
    blowups = sum(len(r.get("blowups", [])) for r in results)
    return (f"{len(results)} logs: {words.count('ok')} ok, {middle}, "
            f"{words.count('ERROR')} errors, {blowups} blow-up{'' if blowups == 1 else 's'}")
