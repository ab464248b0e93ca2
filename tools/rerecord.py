"""Re-record logs after their interface or scene file changed in ways their run does
not see (a comment, a key the log never presses, how the window frames the scene): the
same events through today's files, into a fresh log whose header holds today's files
and hashes. Refuses (and leaves the log alone) unless the new run ends in the same state
as the recording.

    python tools/rerecord.py assets/logs/NAME.jsonl [...]
    python tools/rerecord.py --new-end assets/logs/NAME.jsonl   # a behaviour changed

``--new-end``: the interface changed what this very performance does (its events, a
live take's samples, are the same): the log is written again ending where today's files
end it, if its expectations still pass there; say so when you commit it.

``--step 1/240`` (with ``--new-end``): the log played on another simulation step, each
event at the step nearest its recorded time (as ``puppet replay --step`` moves them):
for a character whose own step changed (``solver: {step: ...}``, issue 29). Its header
then says the new step; refused unless its expectations pass there.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from puppet.timeline.log import Recorder, read_log
from puppet.timeline.replay import apply_log, new_session, setup_for_log


def _script(header: dict) -> tuple[str, str] | None:
    """The reactive script a log was played by (its playtests play it again): today's
    file of that name (assets/scripts/), else the text the header kept; None: none."""
    name, text = header.get("script"), header.get("script_text")
    if not isinstance(name, str) or not isinstance(text, str):
        return None
    from puppet.data.catalog import ROOT

    today = ROOT / "assets" / "scripts" / f"{name}.yaml"
    return name, today.read_text(encoding="utf-8") if today.is_file() else text


def rerecord(path: Path, new_end: bool = False, step: float | None = None) -> str:
    log = read_log(path)
    setup, _ = setup_for_log(log)
    if step is not None:
        from puppet.timeline.other_physics import rescaled

        log = rescaled(log, step)  # the events at the same times on the step
    session = new_session(log, setup)
    h = log.header
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / path.name
        with Recorder(session, out, slowdown=h.get("slowdown"),
                      description=h.get("description"), script=_script(h)):
            apply_log(session, log)
        new = read_log(out)
        if new.end_hash != log.end_hash and not new_end:
            return f"{path}: NOT re-recorded: ends in {new.end_hash}, recorded {log.end_hash}"
        if new.end_hash != log.end_hash:
            import shutil

            from puppet.testing import replay_log

            side = path.parent / (path.stem + ".expect.yaml")
            if side.exists():
                shutil.copy(side, Path(tmp) / side.name)
            failed = replay_log(out).failed
            if failed:
                return (f"{path}: NOT re-recorded: ends in {new.end_hash}, where "
                        + "; ".join(str(f) for f in failed))
        path.write_text(out.read_text(encoding="utf-8"), encoding="utf-8")
    if new.end_hash != log.end_hash:
        return f"{path}: re-recorded, a new end {new.end_hash} (was {log.end_hash})"
    return f"{path}: re-recorded, same end {log.end_hash}"


if __name__ == "__main__":
    args = sys.argv[1:]
    if not args or "-h" in args or "--help" in args:  # (was read as a log's name)
        print(__doc__.strip())
        sys.exit(0 if args else 2)
    step = None
    if "--step" in args:
        from puppet.timeline.other_physics import parse_step

        i = args.index("--step")
        step = parse_step(args[i + 1])
        del args[i:i + 2]
        if "--new-end" not in args:
            sys.exit("rerecord.py: --step goes with --new-end (another step ends elsewhere)")
    new_end = "--new-end" in args
    for arg in args:
        if arg != "--new-end":
            print(rerecord(Path(arg), new_end, step))
