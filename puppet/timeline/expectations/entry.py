"""One ``- KIND: ...`` entry of an ``expect:`` list (``Expectation``, a struct with one
optional field per registered kind, built from ``KINDS``), and a validated list of
them with where they came from (``Expectations``): the checks made before a replay
(bounds nothing can meet, link, state, mode, prop names, windows after the end).
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field as dc_field

import msgspec

from puppet.data.errors import DataError
from puppet.data.playtest_bar import PlaytestBar
from puppet.data.validate import Spec
from puppet.data.yamlfile import Located

# the theme modules register their kinds in KINDS as they are imported
from puppet.timeline.expectations import contacts, flight, grasps, position, posture, states  # noqa: F401
from puppet.timeline.expectations.base import KINDS, Check, Checking


class _Entry(Spec, kw_only=True, dict=True):
    """What every entry does, whatever its kind (the fields are added by ``defstruct``
    below, one per kind). ``_where``: (Located, data path) of the entry, for errors found
    only when evaluating (not a field: ``dict=True`` lets the struct hold it)."""

    def __post_init__(self):
        given = [n for n in self.__struct_fields__ if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("each expectation names exactly one check; got "
                             f"{', '.join(given) or 'none'}")
        setattr(self, given[0], KINDS[given[0]].from_written(getattr(self, given[0])))

    @property
    def kind(self) -> str:
        return next(n for n in self.__struct_fields__ if getattr(self, n) is not None)

    @property
    def value(self) -> Check:
        return getattr(self, self.kind)

    def error(self, message: str, *sub) -> DataError:
        """A DataError at this entry (``sub``: a key inside it) if it came from a file."""
        where = getattr(self, "_where", None)
        if where is None:
            return DataError("expect", None, None, message)
        located, loc = where
        return located.error(loc + sub, message)

    def link(self) -> str | None:
        return getattr(self.value, "link", None)

    def describe(self) -> str:
        return self.value.describe()


Expectation = msgspec.defstruct(
    "Expectation", [(kind, cls.file_type() | None, None) for kind, cls in KINDS.items()],
    bases=(_Entry,), module=__name__, kw_only=True, dict=True, forbid_unknown_fields=True)
Expectation.__doc__ = ("One entry of an expect: list: exactly one of its fields (the kinds, "
                       "KINDS) is given.")


class ExpectFile(Spec, kw_only=True):
    description: str = ""
    expect: list[Expectation]
    # how forgiving the feat must be: ``puppet playtest`` checks it (docs/interfaces.md)
    playtest: PlaytestBar | None = None


# (low, high) fields of a kind's settings: the high one may not be under the low one
# (an entry that nothing can pass); the YAML names (``from_`` is 'from')
BOUND_PAIRS = (("min", "max"), ("from_", "until"), ("x_min", "x_max"), ("y_min", "y_max"),
               ("min_seconds", "max_seconds"), ("min_rms", "max_rms"),
               ("min_root_angle", "max_root_angle"), ("min_count", "max_count"))


def _yaml_name(name: str) -> str:
    return name.removesuffix("_")


def _bounds_problem(v) -> tuple[str, str] | None:
    """(the high field's YAML name, the message) for a pair of bounds that no value can
    meet (max under min, until before from), checked once here for every kind."""
    for low, high in BOUND_PAIRS:
        lo, hi = getattr(v, low, None), getattr(v, high, None)
        if isinstance(lo, bool) or isinstance(hi, bool) or not (
                isinstance(lo, (int, float)) and isinstance(hi, (int, float))):
            continue
        if hi < lo:
            a, b = _yaml_name(low), _yaml_name(high)
            if low == "from_":
                return b, (f"'{b}' ({hi:g} s) is before '{a}' ({lo:g} s): the window is "
                           f"empty; expected '{b}' at or after '{a}'")
            return b, (f"'{b}' ({hi:g}) is less than '{a}' ({lo:g}): nothing can be in "
                       f"that range; expected '{b}' at least '{a}'")
    return None


@dataclass
class Expectations:
    """Validated expectations and where they came from (for errors about link names).
    ``notes``: what loading them would warn about (one line each: a header's entries
    left out for the sidecar's, an empty list)."""

    items: list[Expectation]
    located: Located | None
    loc_prefix: tuple  # data path of the list inside ``located``
    notes: list[str] = dc_field(default_factory=list)

    def __post_init__(self):
        if self.located is not None:
            for i, e in enumerate(self.items):
                e._where = (self.located, self.loc_prefix + (i, e.kind))
        for e in self.items:
            if problem := _bounds_problem(e.value):
                raise e.error(f"{e.kind}: {problem[1]}", problem[0])

    @property
    def touches(self) -> bool:
        """Some entry reads what the links touched (the replay's Sampler records it)."""
        return any(type(e.value).touches for e in self.items)

    def check_names(self, names) -> None:
        """DataError (at the entry) for a state or mode the interface does not define:
        ``names`` has ``state_names`` and ``mode_names`` (a Trajectory, or what
        ``puppet check`` reads from the log's interface versions)."""
        for e in self.items:
            for column, name, sub in getattr(e.value, "names", list)():
                Checking(e).check_name(names, column, name, *sub)

    def check_scene(self, props: list[str], ground: list[str]) -> None:
        """DataError (at the entry) for a prop or a named ground polyline the scene does
        not have (``puppet check`` asks before any replay)."""
        for e in self.items:
            if hasattr(e.value, "check_scene"):
                e.value.check_scene(Checking(e), props, ground)

    def check_windows(self, end: float) -> None:
        """DataError (at its 'from') for a window that begins after ``end`` (s: the
        log's last step), which no sample of the replay can be in."""
        for e in self.items:
            start = getattr(e.value, "from_", None)
            if start is not None and start > end + 1e-9:
                raise e.error(f"'from' ({start:g} s) is after the log's end ({end:.2f} s): "
                              f"no sample is in the window; expected 'from' at most "
                              f"{end:.2f} s", "from")

    def check_links(self, links: list[str]) -> None:
        """DataError (at the entry) for a link the character does not have."""
        for e in self.items:
            named = getattr(e.value, "links", None)
            for i, name in enumerate(named if named is not None else
                                     ([e.link()] if e.link() is not None else [])):
                if name not in links:
                    raise e.error(f"unknown link '{name}'; the character has: "
                                  f"{', '.join(links)}", *(("links", i) if named else ("link",)))
