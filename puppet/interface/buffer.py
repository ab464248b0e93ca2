"""Input buffering: a press made a little before the state that takes it.

A person presses on a rhythm, not on a simulation step: a swap key pressed while the
swing foot is still in the air comes early, not wrong. A state's key with ``buffer:
S`` (data, ``KeyActionSpec.buffer``) also takes a press of its key made up to S seconds
before the state was entered, as long as no binding took that press (fighting games
keep a press made during a move's last frames the same way). This module keeps those
presses; the runtime asks it, whenever a state is entered, for one to act on.
"""

from __future__ import annotations


class InputBuffer:
    def __init__(self, state_bindings: dict, dt: float):
        # only keys some state takes with a buffer are kept
        self.keys = frozenset(chord for table in state_bindings.values()
                              for chord, k in table.items() if k.buffer is not None)
        self.dt = dt
        self.unused: dict[str, int] = {}  # chord -> the step of a press no binding took

    def keep(self, chord: str, now: int) -> None:
        """A press no binding took (a later one of the same key replaces it)."""
        if chord in self.keys:
            self.unused[chord] = now

    def spend(self, chord: str) -> None:
        """The key acted: an older kept press of it is spent with it."""
        self.unused.pop(chord, None)

    def due(self, lookup, now: int):
        """(binding, machine, chord) of a kept press that the binding its key finds now
        (``lookup(chord)``) takes - one with a ``buffer`` reaching back to it - removed
        from the buffer; or None. Presses too old for any buffer stay until replaced
        (another state may keep a longer one)."""
        for chord, at in self.unused.items():
            binding, machine = lookup(chord)
            buffer = getattr(binding, "buffer", None)
            if buffer is not None and now - at <= round(buffer / self.dt):
                del self.unused[chord]
                return binding, machine, chord
        return None

    def get_state(self) -> dict:
        return dict(self.unused)

    def set_state(self, state: dict | None) -> None:
        self.unused = {c: at for c, at in (state or {}).items() if c in self.keys}
