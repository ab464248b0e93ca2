"""Hot reload: notice that the interface file was saved, and check the new text.

Pure (no pygame, no clock of its own): the window calls ``poll(now)`` every frame
with its wall time; the file's modification time (and size) are looked at about
every ``interval`` seconds. A changed file's text is checked the way ``puppet check``
does (``check``, raising DataError); a valid one becomes a "reload" event for
``Session.handle``, an invalid one a one-line error for the HUD while the last good
version keeps running.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from puppet.data.errors import DataError

POLL_INTERVAL = 0.5  # s of wall time between looks at the file


@dataclass
class Change:
    """The file changed: its text, and the one-line error if it is invalid."""

    text: str
    error: str | None = None

    @property
    def ok(self) -> bool:
        return self.error is None


class Reloader:
    def __init__(self, path: str | Path, check: Callable[[str], object] | None = None,
                 interval: float = POLL_INTERVAL, now: float = 0.0):
        self.path = Path(path)
        self.check = check
        self.interval = interval
        self.next_poll = now + interval
        self.seen = self._stamp()
        try:  # the last text read (valid or not)
            self.text: str | None = self.path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            self.text = None

    def _stamp(self):
        try:
            st = self.path.stat()
        except OSError:
            return None
        return st.st_mtime_ns, st.st_size

    def poll(self, now: float) -> Change | None:
        """A Change when the file was saved since the last poll, else None."""
        if now < self.next_poll:
            return None
        self.next_poll = now + self.interval
        stamp = self._stamp()
        if stamp is None or stamp == self.seen:
            return None  # unchanged, or gone for a moment (an editor's atomic save)
        self.seen = stamp
        try:
            text = self.path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            return Change("", f"{self.path}: cannot read: {exc}")
        if text == self.text:
            return None  # touched, same content
        self.text = text
        if self.check is not None:
            try:
                self.check(text)
            except DataError as exc:
                return Change(text, str(exc))
        return Change(text)
