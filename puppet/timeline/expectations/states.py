"""What the interface was doing (its state machine's state, its mode) and the exact
state the physics ended in (its hash).

A state or mode the interface does not define is a DataError at the entry, raised when
the expectations are evaluated: the interface is only known for sure once replayed
(the header's copy, or the versions a reload brought in). "Stayed" is as fine as the
sampling: a state left and re-entered between two samples goes unseen. Margins in
seconds (how long it was out of the state, or has been in it at the end).
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from puppet.data.ranges import Time
from puppet.data.validate import field
from puppet.timeline.expectations.base import Check, Checking
from puppet.timeline.expectations.measure import named, samples_in, seconds_of, window_text


class StayedIn(Check, kw_only=True):
    """The common part of stayed_in_state and stayed_in_mode: the time window. The
    shorthand ``stayed_in_state: NAME`` is the whole run."""

    column: ClassVar[str]  # the Trajectory column and the key naming it: state or mode
    unit = "s"
    from_: Time | None = field(name="from", default=None)  # s: window start (default: the start)
    until: Time | None = None  # s: window end (default: the end; before 'from': refused
    # with every kind's bounds, Expectations)

    @classmethod
    def file_type(cls) -> Any:
        return cls | str

    @classmethod
    def from_written(cls, value):
        return cls(**{cls.column: value}) if isinstance(value, str) else value

    @property
    def name(self) -> str:
        return getattr(self, self.column)

    def names(self) -> list[tuple[str, str, tuple]]:
        return [(self.column, self.name, (self.column,))]

    def describe(self) -> str:
        return f"{self.kind} {self.name}{window_text(self)}"

    def evaluate(self, traj, at: Checking):
        """In the state (or mode) at every sample of the window; else where it first
        was not: the state it left for, or the one it was in when the window began."""
        at.check_name(traj, self.column, self.name, self.column)  # (shorthand: the entry)
        t, seen = traj.t, getattr(traj, self.column)
        idx = samples_in(t, self.from_, self.until)
        if len(idx) == 0:
            return self.no_samples(t)
        off = idx[seen[idx] != self.name]
        if len(off) == 0:
            return self.outcome(True, f"in '{self.name}' from t = {t[idx[0]]:.2f} s "
                                      f"to {t[idx[-1]]:.2f} s", 0.0)
        k = int(off[0])
        if k == idx[0]:
            what = f"in {named(seen[k])}, not '{self.name}', at t = {t[k]:.2f} s"
        else:
            what = f"left '{self.name}' for {named(seen[k])} at t = {t[k]:.2f} s"
        return self.outcome(False, what, -seconds_of(len(off), t))



class StayedInState(StayedIn, kw_only=True):
    """The interface's state machine in ``state`` at every sample of the window."""

    kind = "stayed_in_state"
    column: ClassVar[str] = "state"
    state: str  # the interface state it must stay in


class StayedInMode(StayedIn, kw_only=True):
    """The interface's mode ``mode`` at every sample of the window."""

    kind = "stayed_in_mode"
    column: ClassVar[str] = "mode"
    mode: str  # the interface mode it must stay in


class AtEnd(Check, kw_only=True):
    """The common part of in_state_at_end and in_mode_at_end: written as the name."""

    column: ClassVar[str]
    written: ClassVar = str
    unit = "s"

    @classmethod
    def from_written(cls, value):
        return cls(**{cls.column: value}) if isinstance(value, str) else value

    @property
    def name(self) -> str:
        return getattr(self, self.column)

    def names(self) -> list[tuple[str, str, tuple]]:
        return [(self.column, self.name, ())]

    def describe(self) -> str:
        return f"{self.kind} {self.name}"

    def evaluate(self, traj, at: Checking):
        """The state at the end and since when; the margin is how long the last state
        lasted (+ the named one, - another)."""
        at.check_name(traj, self.column, self.name)
        seen = getattr(traj, self.column)
        changed = np.flatnonzero(seen != seen[-1])
        since = traj.t[changed[-1] + 1] if len(changed) else traj.t[0]
        last = len(seen) - (changed[-1] + 1 if len(changed) else 0)
        ok = seen[-1] == self.name
        return self.outcome(ok, f"in {named(seen[-1])} at the end (since t = {since:.2f} s)",
                            seconds_of(last, traj.t) * (1 if ok else -1))


class InStateAtEnd(AtEnd, kw_only=True):
    """The interface's state machine in ``state`` at the end."""

    kind = "in_state_at_end"
    column: ClassVar[str] = "state"
    state: str


class InModeAtEnd(AtEnd, kw_only=True):
    """The interface's mode at the end."""

    kind = "in_mode_at_end"
    column: ClassVar[str] = "mode"
    mode: str


class FinalHash(Check, kw_only=True):
    """The exact state the physics ended in: its hash (``puppet replay`` prints it)."""

    kind = "final_hash"
    written: ClassVar = str
    hash: str

    @classmethod
    def from_written(cls, value):
        return cls(hash=value) if isinstance(value, str) else value

    def describe(self) -> str:
        return f"final_hash {self.hash}"

    def evaluate(self, traj, at: Checking):
        ok = at.final_hash == self.hash
        return self.outcome(ok, f"final hash {at.final_hash}", 0.0 if ok else None)
