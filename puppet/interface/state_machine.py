"""The control state machine: which bindings and maps are live, and when to move on.

States are data (``states:`` in an interface); a key's ``goto`` or a transition on a
timer or a sensor condition changes state. Times are in whole steps since entering,
so the machine replays bit-identically and its state is two plain values.
"""

from __future__ import annotations

from puppet.interface.conditions import compile_condition


class StateMachine:
    def __init__(self, spec, character, dt: float):
        self.states = spec.states
        # Sensor conditions are polled at the control rate, on steps that are multiples
        # of ``every`` (absolute, so how advance() calls are split does not matter).
        self.every = max(1, round(1.0 / (spec.control_rate * dt)))
        self.initial = spec.start_state
        # state -> [(to, min steps in state, predicate or None)]
        self.transitions = {
            name: [(t.to, round((t.after or 0.0) / dt),
                    compile_condition(t.when, character) if t.when is not None else None)
                   for t in state.transitions]
            for name, state in spec.states.items()}
        self.current = self.initial
        self.entered = 0

    def enter(self, name: str, now: int) -> None:
        self.current, self.entered = name, now

    def next_check(self, earliest: int) -> int | None:
        """The first step >= earliest at which a transition could fire."""
        best = None
        every = self.every
        for _, after, predicate in self.transitions[self.current]:
            at = max(earliest, self.entered + after)
            if predicate is not None:
                at = -(-at // every) * every
            if best is None or at < best:
                best = at
        return best

    def due(self, now: int) -> str | None:
        """The state to go to now, if a transition fires (first listed wins)."""
        for to, after, predicate in self.transitions[self.current]:
            if now < self.entered + after:
                continue
            if predicate is None or (now % self.every == 0 and predicate(None)):
                return to
        return None

    def get_state(self) -> list:
        return [self.current, self.entered]

    def set_state(self, state) -> None:
        self.current, self.entered = state
