"""The shape of an expectation kind: one class carries its settings (a data-file struct),
how it is said (``describe``) and how it is checked (``evaluate``); ``KINDS`` maps each
kind's key in a file to its class.

A kind is added by writing one subclass of ``Check`` with a ``kind`` (its key) in one
of the theme modules and a section in docs/expectations.md (a test holds the two
together); the entry struct (``Expectation``) is built from ``KINDS``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from puppet.data.errors import DataError
from puppet.data.validate import Spec
from puppet.timeline.expectations.outcome import Outcome

if TYPE_CHECKING:
    from puppet.timeline.expectations.entry import Expectation

KINDS: dict[str, type[Check]] = {}  # key in a file -> class, in the order defined


@dataclass
class Checking:
    """What a check needs besides the run: the entry it came from (errors found only
    when evaluating are reported at its place in the file) and the run's final hash."""

    entry: Expectation | None
    final_hash: str = ""

    def error(self, message: str, *sub) -> DataError:
        if self.entry is None:
            return DataError("expect", None, None, message)
        return self.entry.error(message, *sub)

    def check_link(self, traj, name: str, *sub) -> None:
        """DataError at ``sub`` for a link the character does not have."""
        if name not in traj.links:
            raise self.error(f"unknown link '{name}'; the character has: "
                             f"{', '.join(traj.links)}", *sub)

    def check_name(self, traj, column: str, name: str, *sub) -> None:
        """DataError (at the entry) for a state or mode the interface does not define."""
        names = getattr(traj, f"{column}_names")
        if name not in names:
            have = (f"the interface has: {', '.join(names)}" if names
                    else f"the interface has no {column}s")
            raise self.error(f"unknown {column} '{name}'; {have}", *sub)


class Check(Spec, kw_only=True):
    """Base of every expectation kind. A subclass sets ``kind`` (its key in a file),
    ``unit`` (its margin's), and writes ``describe`` and ``evaluate``. ``written``: the
    type an entry may give instead of the mapping (``upright_at_end: true``,
    ``stayed_in_state: NAME``), turned into the struct by ``from_written``."""

    kind: ClassVar[str]
    unit: ClassVar[str] = ""  # the margin's unit
    written: ClassVar[Any] = None  # a shorthand's type (bool, str), or None
    touches: ClassVar[bool] = False  # reads Trajectory.touches (the sampler records them)

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "kind" in cls.__dict__:
            KINDS[cls.kind] = cls

    @classmethod
    def file_type(cls) -> Any:
        """The type an entry's value is validated as (the struct, or a shorthand too)."""
        return cls if cls.written is None else cls.written

    @classmethod
    def from_written(cls, value) -> Check:
        """The struct for a value as validated (a shorthand made whole)."""
        return value

    def describe(self) -> str:
        raise NotImplementedError(self.kind)

    def evaluate(self, traj, at: Checking) -> Outcome:
        raise NotImplementedError(self.kind)

    def outcome(self, passed: bool, measured: str, margin: float | None,
                unit: str | None = None) -> Outcome:
        """This check's Outcome: its description, the verdict, what was measured and
        the margin (in ``unit``, default the kind's)."""
        return Outcome(self.describe(), bool(passed), measured, self.kind, margin,
                       self.unit if unit is None else unit)

    def no_samples(self, t) -> Outcome:
        return self.outcome(False, f"no samples in the window (the run is {t[-1]:.2f} s)",
                            None)
