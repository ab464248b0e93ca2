"""Write recorded gestures into an interface file as text, leaving the rest alone.

The designer's comments and layout must survive, so the file is never round-tripped
through a YAML dumper: the top-level ``gestures:`` block (its key line and every
indented line after it) is replaced, or a new block is appended at the end.
"""

from __future__ import annotations

import json
import re

POINTS_PER_LINE = 4
_TOP_KEY = re.compile(r"^gestures\s*:")


def _num(v: float) -> str:
    v = float(v)
    return str(int(v)) if v.is_integer() else repr(v)


def gestures_block(gestures) -> str:
    """The YAML text of a ``gestures:`` block (``GestureSpec``s or dicts)."""
    lines = ["gestures:  # recorded mouse paths: [t (s), x, y]; F2 records, F3 saves"]
    for g in gestures:
        g = g if isinstance(g, dict) else {"key": g.key, "description": g.description,
                                           "path": g.path}
        lines.append(f"  - key: {json.dumps(g['key'])}")
        if g.get("description"):
            lines.append(f"    description: {json.dumps(g['description'])}")
        points = [f"[{_num(t)}, {_num(x)}, {_num(y)}]" for t, x, y in g["path"]]
        rows = [", ".join(points[i:i + POINTS_PER_LINE])
                for i in range(0, len(points), POINTS_PER_LINE)]
        lines.append("    path: [" + (",\n           ".join(rows)) + "]")
    return "\n".join(lines) + "\n"


def _block_span(lines: list[str]) -> tuple[int, int] | None:
    """[start, end) line indices of the top-level gestures block, if there is one:
    its key line and the indented (or blank) lines after it, not counting blank or
    comment lines that trail it (they belong to what follows)."""
    for start, line in enumerate(lines):
        if _TOP_KEY.match(line):
            end = start + 1
            last = start + 1
            while end < len(lines):
                text = lines[end]
                # indented, or an indentless list item ("- key: h" under "gestures:")
                inside = text[:1].isspace() or text.startswith("-")
                if text.strip() and not inside and not text.startswith("#"):
                    break  # the next top-level key
                if text.strip() and inside and not text.lstrip().startswith("#"):
                    last = end + 1
                end += 1
            return start, last
    return None


def replace_gestures(text: str, gestures) -> str:
    """``text`` with its gestures block replaced by ``gestures`` (appended if it has
    none; removed if ``gestures`` is empty). Every other byte is kept."""
    block = gestures_block(gestures) if gestures else ""
    lines = text.splitlines(keepends=True)
    span = _block_span(lines)
    if span is None:
        if not block:
            return text
        sep = "" if not text or text.endswith("\n") else "\n"
        return text + sep + block
    start, end = span
    return "".join(lines[:start]) + block + "".join(lines[end:])
