"""The last playtest figures, kept where the app finds them: recordings/playtests.json.

``puppet playtest`` writes each log's figure there (keyed by the log and by the
interface it plays), and the window shows the last one of the interface being played
(the HUD's top-left panel). It is a small JSON file in the window's own folder
(recordings/, not shipped); a file that cannot be read or written is ignored: the
figure is a convenience, never a reason to fail.
"""

from __future__ import annotations

import datetime
import json
import os
from pathlib import Path

from puppet.data.catalog import FOLDERS, ROOT

STORE = Path(os.environ.get("PUPPET_PLAYTESTS") or ROOT / FOLDERS["recording"][0]
             / "playtests.json")
MAX_ENTRIES = 500  # logs kept (the oldest go first)


def _read(path: Path) -> dict:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {"logs": {}, "interfaces": {}}
    if not isinstance(data, dict):
        return {"logs": {}, "interfaces": {}}
    for key in ("logs", "interfaces"):
        if not isinstance(data.get(key), dict):
            data[key] = {}
    return data


def save(figures: list[dict], path: Path | None = None, now=None) -> Path | None:
    """Add figures ({log, interface, passes, tries, noise, ...}) to the store; the path
    written, or None when it could not be."""
    path = Path(path or STORE)
    data = _read(path)
    stamp = (now or datetime.datetime.now()).isoformat(timespec="seconds")
    for f in figures:
        entry = dict(f, date=stamp)
        data["logs"].pop(f["log"], None)  # re-inserted last: the newest
        data["logs"][f["log"]] = entry
        data["interfaces"].pop(f["interface"], None)
        data["interfaces"][f["interface"]] = entry
    while len(data["logs"]) > MAX_ENTRIES:
        data["logs"].pop(next(iter(data["logs"])))
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + f".{os.getpid()}.tmp")
        tmp.write_text(json.dumps(data, indent=1), encoding="utf-8")
        os.replace(tmp, path)
    except OSError:
        return None
    return path


def last_for(interface: str, path: Path | None = None) -> dict | None:
    """The last figure recorded for an interface (by its name), or None."""
    entry = _read(Path(path or STORE))["interfaces"].get(interface)
    return entry if isinstance(entry, dict) else None


def figure_line(entry: dict | None) -> str:
    """How the HUD says a figure: 'playtest biped-backflip: 2/20 pass at human'."""
    if not entry:
        return ""
    try:
        return (f"playtest {entry['log']}: {int(entry['passes'])}/{int(entry['tries'])} pass "
                f"at {entry['noise']}")
    except (KeyError, TypeError, ValueError):
        return ""
