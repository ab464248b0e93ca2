"""The protocol every controller follows (see the package's docstring)."""

from __future__ import annotations

from typing import Protocol

from puppet.interface.ownership import Owner

# What ``tick`` may return when, at this step, it only waited: it changed nothing at all
# and its ``next_wakeup`` stands, or is the next step (a sequence holding its pose, or
# testing its step's ``until`` that does not hold yet; a control-rate controller between
# its steps). Also a controller that works at every step (``control_rate: 480``: a blend
# writing plain targets, sensor maps) and only wrote targets: no joint arrived, was
# taken back or held in another frame, no other controller started, and its next
# wake-up is the next step. The arbiter then keeps its schedule (the earliest wake-up
# it had, else the next step) instead of asking every controller again (the state
# machines poll each frame: the hot path). Anything else (None) means "something may
# have changed": the arbiter reschedules.
WAITED = "waited"


class Controller(Protocol):
    BUSY: str  # the name of an attribute that is truthy whenever the controller has work
    # (running sequence, armed grasps...): the arbiter asks ``next_wakeup`` only then
    def tick(self, step: int) -> str | None:
        """Do what is due at ``step`` (called before stepping from it); ``WAITED`` if
        there was nothing to do."""

    def next_wakeup(self, earliest: int) -> int | None:
        """The first step >= ``earliest`` at which ``tick`` must run; None when idle."""

    def owners(self) -> set[Owner]:
        """The owners under which this controller holds joints now."""

    def get_state(self):
        """Plain values (JSON-ready) that ``set_state`` takes back."""

    def set_state(self, state) -> None: ...

    def adopt(self, old, same, now: int) -> set[Owner]:
        """Continue what ``old`` (the controller of the replaced interface) runs where
        ``same(kind, name)`` says this interface defines it the same way; returns the
        owners kept."""

    def stop(self) -> None:
        """End everything running (a reset)."""
