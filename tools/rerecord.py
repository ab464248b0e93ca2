"""Re-record logs after their interface or scene file changed in ways their run does
not see (a comment, a key the log never presses, how the window frames the scene): the
same events through today's files, into a fresh log whose header holds today's files
and hashes. Refuses (and leaves the log alone) unless the new run ends in the same state
as the recording.

With ``--new-end``, for a change that moves the run on purpose (the control layer
solving at another rate): the same events are re-recorded if the new run passes every
expectation of the log's sidecar (its end state is then the new one).

    python tools/rerecord.py [--new-end] assets/logs/NAME.jsonl [...]
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

from puppet.timeline.expectations.files import sidecar_path
from puppet.timeline.log import Recorder, read_log
from puppet.timeline.replay import apply_log, new_session, replay, setup_for_log


def rerecord(path: Path, new_end: bool = False) -> str:
    log = read_log(path)
    setup, _ = setup_for_log(log)
    session = new_session(log, setup)
    h = log.header
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / path.name
        with Recorder(session, out, slowdown=h.get("slowdown"),
                      description=h.get("description")):
            apply_log(session, log)
        new = read_log(out)
        if new.end_hash != log.end_hash:
            if not new_end:
                return (f"{path}: NOT re-recorded: ends in {new.end_hash}, recorded "
                        f"{log.end_hash}")
            side = sidecar_path(path)  # the log's expectations, beside the new run too
            if side.is_file():
                shutil.copy(side, sidecar_path(out))
            result = replay(out, check=True)
            failed = [str(o) for o in result.failed]
            if failed:
                return f"{path}: NOT re-recorded: " + "; ".join(failed)
        path.write_text(out.read_text(encoding="utf-8"), encoding="utf-8")
    if new.end_hash != log.end_hash:
        return (f"{path}: re-recorded, new end {new.end_hash} (was {log.end_hash}), "
                "every expectation holds")
    return f"{path}: re-recorded, same end {log.end_hash}"


if __name__ == "__main__":
    args = sys.argv[1:]
    new_end = "--new-end" in args
    for arg in args:
        if arg != "--new-end":
            print(rerecord(Path(arg), new_end))
