"""Where expectations come from: a sidecar ``LOG.expect.yaml`` next to the log, the
log header's ``"expect": [...]`` list, or Python data (a test's). The sidecar wins:
the header's entries are then not checked, and a note says so; so does an empty list.
"""

from __future__ import annotations

from pathlib import Path

from puppet.data.errors import DataError
from puppet.data.validate import validate
from puppet.data.yamlfile import Located, load_file
from puppet.timeline.expectations.entry import Expectation, Expectations, ExpectFile


def sidecar_path(log_path: str | Path) -> Path:
    """``NAME.expect.yaml`` next to ``NAME.jsonl`` (``NAME.jsonl.expect.yaml`` also works)."""
    p = Path(log_path)
    plain = p.with_name(p.name.removesuffix(".jsonl") + ".expect.yaml")
    if not plain.is_file():
        other = p.with_name(p.name + ".expect.yaml")
        if other.is_file():
            return other
    return plain


def _one_check_each(located: Located) -> None:
    """An entry naming two checks (or none) of the known kinds, refused in one line at
    the entry (msgspec's words would add the entry as a cut Python dict)."""
    items = located.data.get("expect") if isinstance(located.data, dict) else None
    if not isinstance(items, list):
        return
    kinds = Expectation.__struct_fields__
    for i, entry in enumerate(items):
        if not isinstance(entry, dict) or any(k not in kinds for k in entry):
            continue  # not a mapping, or an unknown key: validate says what is wrong
        if len(entry) != 1:
            named = (f"names {len(entry)}: {', '.join(map(str, entry))}" if entry
                     else "names none")
            raise located.error(("expect", i), f"each expectation names exactly one check; "
                                               f"this entry {named} (expected one per '- ' "
                                               f"entry)")


def validate_expect_file(located: Located) -> ExpectFile:
    """A sidecar file's (or the header's) ``expect:`` list validated: each entry one
    check, every pair of bounds one that a value can meet."""
    _one_check_each(located)
    spec = validate(located, ExpectFile)
    Expectations(spec.expect, located, ("expect",))  # the bounds, at their entries
    return spec


def load_expectations(log_path: str | Path, header: dict) -> Expectations:
    """The sidecar file's expectations if there is one, else the header's: the sidecar
    wins, and a header's own entries then left out are a note; so is an empty list
    (a replay --check that checks nothing but the end state)."""
    side = sidecar_path(log_path)
    if side.is_file():
        located = load_file(side)
        spec = validate_expect_file(located)
        result = Expectations(spec.expect, located, ("expect",))
        if header.get("expect"):
            result.notes.append(f"{log_path}: warning: the header's {len(header['expect'])} "
                                f"expectation(s) are not checked: the sidecar {side.name} "
                                f"replaces them (the sidecar wins)")
    else:
        raw = header.get("expect") or []
        located = Located(str(log_path), {"expect": raw}, value_pos={(): (1, 1)})
        spec = validate_expect_file(located)
        result = Expectations(spec.expect, located, ("expect",))
        side = None
    if not spec.expect and (side is not None or "expect" in header):
        result.notes.append(f"{side or log_path}: warning: 'expect' is an empty list: "
                            "no expectation is checked")
    return result


def parse_expectations(items: list, where: str = "expect") -> Expectations:
    """Expectations given as Python data (e.g. by a test): a list of entries."""
    if not isinstance(items, (list, tuple)):
        raise DataError(where, None, None, f"expected a list of expectation entries "
                                           f"(e.g. [{{'never_fell': True}}]), got "
                                           f"{type(items).__name__} {_short(items)}")
    located = Located(where, {"expect": list(items)})
    return Expectations(validate_expect_file(located).expect, located, ("expect",))


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
