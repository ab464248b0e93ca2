"""What a search has done so far, on disk beside its output (``NAME.tune.json``), so an
interrupted search goes on where it stopped.

The search is deterministic: from the same spec and seed it asks for the same tries
in the same order. So the state is only the tries already played - each try's key (a
hash of its stage's starting input and its parameters) and its result - and resuming
is running the search again with those results looked up instead of played. A try's key
holds what its result depends on - its stage as written and the input before it - so a
spec edited in a later stage, another seed or budget still finds the tries it asks
again. The file is written after every batch (to a temporary file, then renamed: a kill
never leaves half of one). Other interface, character or scene files, another puppet
version or tuning code make the old results another search's: they are set aside and
the search starts afresh (and says so).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

FORMAT = "puppet-tune-state"
VERSION = 1


def digest(*parts) -> str:
    h = hashlib.sha1()
    for p in parts:
        h.update(json.dumps(p, sort_keys=True, default=str).encode())
        h.update(b"\0")
    return h.hexdigest()[:20]


class State:
    """The tries played (key -> result as a dict), loaded from and saved to ``path``
    (None: kept in memory only)."""

    def __init__(self, path: Path | None, fingerprint: str):
        self.path = path
        self.fingerprint = fingerprint
        self.tries: dict[str, dict] = {}
        self.note = ""  # what loading found, for the user
        if path is not None and path.is_file():
            try:
                data = json.loads(path.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                data = None
            if not isinstance(data, dict) or data.get("format") != FORMAT:
                self.note = f"{path}: not a search's state file: starting afresh"
            elif data.get("fingerprint") != fingerprint:
                self.note = (f"{path}: from other interface, character or scene files or "
                             "another puppet: starting afresh")
            else:
                self.tries = dict(data.get("tries") or {})
                self.note = f"resuming: {len(self.tries)} tries already played ({path})"

    def save(self) -> None:
        if self.path is None:
            return
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(self.path.name + ".tmp")
        tmp.write_text(json.dumps({"format": FORMAT, "version": VERSION,
                                   "fingerprint": self.fingerprint, "tries": self.tries},
                                  separators=(",", ":")), encoding="utf-8")
        os.replace(tmp, self.path)
