"""Who writes each joint's target: "the most recent action wins", per joint.

A running controller (a sequence, a gesture, a reach) *owns* the joints it drives and
writes only those; an instant write (a pose, a set or adjust, a map that updates)
takes its joints back, so the controller carries on with the rest and ends when it
has none. A joint nobody owns keeps the target it was last given.
"""

from __future__ import annotations

from typing import NamedTuple


class Owner(NamedTuple):
    """A controller that can own joints: its kind and, for reaches, the chain. (A named
    tuple: owners are compared on every tick, and tuples compare in C.)"""

    kind: str  # "sequence", "gesture", "reach", "frame", "feedback" or "blend"
    name: str = ""

    def __str__(self) -> str:
        return f"{self.kind}:{self.name}" if self.name else self.kind


SEQUENCE = Owner("sequence")
GESTURE = Owner("gesture")
FRAME = Owner("frame")  # a target held in another frame (controllers/frame.py)
FEEDBACK = Owner("feedback")  # a map that reads the figure's sensors
BLEND = Owner("blend")  # a pose or set reached over time (controllers/blend.py)


def reach_owner(chain: str) -> Owner:
    return Owner("reach", chain)


class JointOwners:
    """The owner table: joint -> Owner, for joints a running controller drives."""

    def __init__(self):
        self.table: dict[str, Owner] = {}

    def __bool__(self) -> bool:
        return bool(self.table)

    def claim(self, joints, owner: Owner) -> None:
        for joint in joints:
            self.table[joint] = owner

    def take(self, joints) -> None:
        """Instant writes take joints back from whoever runs them."""
        table = self.table
        if table:
            for joint in joints:
                table.pop(joint, None)

    def drop(self, owner: Owner) -> None:
        """``owner`` ends: its joints are nobody's."""
        for joint in [j for j, o in self.table.items() if o == owner]:
            del self.table[joint]

    def owned(self, owner: Owner) -> set[str]:
        return {j for j, o in self.table.items() if o == owner}

    def holds_any(self, owner: Owner) -> bool:
        return owner in self.table.values()

    def keep_only(self, owners: set[Owner]) -> None:
        """Forget every owner not in ``owners`` (a hot reload ended them)."""
        self.table = {j: o for j, o in self.table.items() if o in owners}

    def get_state(self) -> list:
        return [[j, o.kind, o.name] for j, o in self.table.items()]

    def set_state(self, state) -> None:
        self.table = {j: Owner(kind, name) for j, kind, name in state}
