"""Numbers of an interface file changed in place: the text a try reloads, and the file
a designer gets back (``NAME.interface.yaml``), comments and layout kept.

A place is a dotted path into the file's data, list items by index:
``gains.ankle_near.max_torque``, ``modes.stepping.0.to.1``; ``-states.s.maps.0.to.1``
writes the value negated (a map's slope written ``to: [v, -v]``). Each number is replaced
where it is written (its line and column as the YAML reader found them), so the file
differs from the original only in those numbers.
"""

from __future__ import annotations

import re

from puppet.data.yamlfile import Located, load_text

_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def _path(place: str) -> tuple:
    return tuple(int(k) if k.lstrip("-").isdigit() else k for k in place.split("."))


def lookup(data, place: str) -> tuple[float | None, str | None]:
    """(the number at ``place``, None) or (None, what is wrong)."""
    node = data
    place = place.lstrip("-")
    for key in _path(place):
        in_map = isinstance(node, dict) and key in node
        in_list = (isinstance(node, list) and isinstance(key, int)
                   and -len(node) <= key < len(node))
        if in_map or in_list:
            node = node[key]
        else:
            return None, f"no '{key}' there"
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        return None, f"holds {type(node).__name__} {node!r}, not a number"
    return float(node), None


def _fmt(value: float) -> str:
    text = f"{round(float(value), 4):.4f}".rstrip("0")
    return text + "0" if text.endswith(".") else text


def with_values(text: str, where: str, values: dict[str, float]) -> str:
    """``text`` with the number at each place replaced by its value (rounded to 1e-4)."""
    located: Located = load_text(text, where)
    lines = text.split("\n")
    spots = []
    for place, value in values.items():
        pos = located.value_pos.get(_path(place))
        if pos is None or lookup(located.data, place)[1]:
            raise ValueError(f"{where}: {place}: not a number of the file")
        spots.append((pos, _fmt(value)))
    # right to left on each line: a replacement does not move the ones before it
    for (line, col), new in sorted(spots, reverse=True):
        row = lines[line - 1]
        m = _NUMBER.match(row, col - 1)
        if m is None:
            raise ValueError(f"{where}:{line}:{col}: expected a number written there")
        lines[line - 1] = row[:m.start()] + new + row[m.end():]
    return "\n".join(lines)


def interface_values(params: list, values: dict) -> dict[str, float]:
    """place -> value of the interface parameters among ``params`` (``spec.Param``); a
    place written ``-PLACE`` takes the value negated (a map's ``to: [v, -v]``)."""
    out = {}
    for p in params:
        if p.interface:
            for place in p.interface:
                negated = place.startswith("-")
                out[place.lstrip("-")] = -float(values[p.name]) if negated else float(
                    values[p.name])
    return out
