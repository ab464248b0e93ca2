"""What a replay may say about the files a log made puppet read beside it: nothing of
what they hold (issue 32). A log someone sent you names a file of yours beside it; the
error of a session that cannot be set up from it would quote its values (a validation
error's "got [...]", a list of its joints), so these errors name the files and the
command that shows them instead (``puppet check FILE``, for files that are yours)."""

from __future__ import annotations

from pathlib import Path

from puppet.data.catalog import Setup, in_catalog
from puppet.data.errors import DataError
from puppet.timeline.log import Log


def unquoted_error(log: Log, found: list, hint: str = "") -> DataError:
    """The error of a log whose setup failed after it made puppet read files beside it
    (``found``, outside the catalog): their errors (and the checks against them, a
    joint the interface names that the character lacks...) would quote what those
    files hold, which a log someone sent you must not make puppet print. So the error
    names the files and the command that shows it, for files that are yours."""
    names = ", ".join(sorted({p.name for p in found}))
    paths = " ".join(sorted({str(p) for p in found}))
    return DataError(log.path, 1, None,
                     f"header: the files it names beside the log ({names}) do not make a "
                     f"valid session; the error is not shown, as it could quote a file the "
                     f"log made puppet read (puppet check {paths} shows it){hint}")


def reload_error(log: Log, line: int | None, setup: Setup, exc: DataError) -> DataError:
    """The error of a reload event (at ``line``) whose interface text fails: checked
    against a character or scene beside the log, it is not quoted."""
    beside = sorted({Path(p).name for p in (setup.character_path, setup.scene_path)
                     if not in_catalog(p)})
    if beside:
        return DataError(log.path, line, None,
                         f"cannot apply this event: the reloaded interface does not fit the "
                         f"files beside the log ({', '.join(beside)}); the error is not "
                         "shown, as it could quote them")
    return DataError(log.path, line, None, f"cannot apply this event: {exc}")
