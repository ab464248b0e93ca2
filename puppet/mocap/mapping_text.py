"""A mapping written out as YAML, in the shipped files' layout (one segment or channel a
line), for ``puppet mocap mapping CLIP > my.yaml``: a file ``puppet check`` takes and
that reads back to the very same mapping (numbers written as Python writes them, the
shortest text that reads back to the same bits; names quoted where YAML would read
them otherwise)."""

from __future__ import annotations

import json
import re

from puppet.data.mappings import MappingSpec

_PLAIN = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*")
_YAML_WORDS = {"y", "n", "yes", "no", "on", "off", "true", "false", "null", "nan", "inf"}


def scalar(value) -> str:
    """A value as a YAML scalar: numbers exact, text plain where safe, else quoted."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(float(value)) if isinstance(value, float) else str(value)
    text = str(value)
    if _PLAIN.fullmatch(text) and text.lower() not in _YAML_WORDS:
        return text
    return json.dumps(text)  # a YAML double-quoted string


def _flow(pairs) -> str:
    return "{" + ", ".join(f"{k}: {_value(v)}" for k, v in pairs) + "}"


def _value(v) -> str:
    if isinstance(v, dict):
        return _flow(v.items())
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return scalar(v)


def _folded(text: str, width: int = 84) -> list[str]:
    words, lines, line = text.split(), [], "  "
    for w in words:
        if len(line) + len(w) + 1 > width and line.strip():
            lines.append(line.rstrip())
            line = "  "
        line += w + " "
    if line.strip():
        lines.append(line.rstrip())
    return lines


def mapping_yaml(spec: MappingSpec, comments: list[str] = ()) -> str:
    """The mapping as a YAML file (``comments`` first, each a ``#`` line)."""
    out = [f"# {c}" for c in comments]
    out.append(f"name: {scalar(spec.name)}")
    if spec.character is not None:
        out.append(f"character: {scalar(spec.character)}")
    if spec.description:
        out.append(f"description: {scalar(spec.description)}")
    if spec.notes:
        out.append("notes: >")
        out += _folded(spec.notes)
    s = spec.source
    source = [("up", s.up), ("unit", s.unit), ("handedness", s.handedness)]
    if tuple(s.scale) != (1.0, 1.0, 1.0):
        source.append(("scale", list(s.scale)))
    out.append(f"source: {_flow(source)}")
    plane = spec.plane if isinstance(spec.plane, str) else list(spec.plane)
    out.append(f"plane: {_value(plane)}")
    if spec.facing is not None:
        f = spec.facing
        pairs = ([("left", f.left), ("right", f.right)] if f.left is not None
                 else [("back", f.back), ("front", f.front)])
        out.append(f"facing: {_flow(pairs)}")
    out.append(f"size: {scalar(spec.size)}")
    out.append(f"root: {_flow([('point', spec.root.point), ('floor', spec.root.floor)])}")
    width = max(len(n) for n in spec.segments) + 1
    out.append("segments:")
    for name, seg in spec.segments.items():
        rest = seg.rest if isinstance(seg.rest, str) else float(seg.rest)
        pairs = [("from", seg.start), ("to", seg.to)] + ([] if rest == "down" else
                                                          [("rest", rest)])
        out.append(f"  {(scalar(name) + ':').ljust(width)} {_flow(pairs)}")
    if spec.channels:
        width = max(len(n) for n in spec.channels) + 1
        out.append("channels:")
        for name, ch in spec.channels.items():
            pairs = [("segment", ch.segment)]
            if ch.relative_to is not None:
                pairs.append(("relative_to", ch.relative_to))
            if ch.offset != 0.0:
                pairs.append(("offset", ch.offset))
            if ch.scale != 1.0:
                pairs.append(("scale", ch.scale))
            out.append(f"  {(scalar(name) + ':').ljust(width)} {_flow(pairs)}")
    if spec.effectors:
        out.append("effectors:")
        out += [f"  {scalar(k)}: {scalar(v)}" for k, v in spec.effectors.items()]
    if spec.clearance is not None:
        c = spec.clearance
        out.append(f"clearance: {_flow([('points', c.points), ('standing', c.standing)])}")
    if spec.com:
        out.append("com:")
        out += [f"  {scalar(k)}: {scalar(v)}" for k, v in spec.com.items()]
    f = spec.filter
    out.append(f"filter: {_flow([('cutoff', f.cutoff), ('beta', f.beta)])}")
    return "\n".join(out) + "\n"
