"""The protocol every controller follows (see the package's docstring)."""

from __future__ import annotations

from typing import Protocol

from puppet.interface.ownership import Owner


class Controller(Protocol):
    BUSY: str  # the name of an attribute that is truthy whenever the controller has work
    # (running sequence, armed grasps...): the arbiter asks ``next_wakeup`` only then
    def tick(self, step: int) -> None:
        """Do what is due at ``step`` (called before stepping from it)."""

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
