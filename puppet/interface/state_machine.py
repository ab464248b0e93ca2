"""The control state machine: which bindings and maps are live, and when to move on.

States are data (``states:`` in an interface); a key's ``goto`` or a transition on a
timer or a sensor condition changes state. Times are in whole steps since entering,
so the machine replays bit-identically and its state is two plain values.
"""

from __future__ import annotations

from puppet.interface.conditions import compile_test, reader


class StateMachine:
    def __init__(self, spec, character, dt: float):
        # Sensor conditions are polled at the control rate, on steps that are multiples
        # of ``every`` (absolute, so how advance() calls are split does not matter).
        self.every = max(1, round(1.0 / (spec.control_rate * dt)))
        self.initial = spec.start_state
        # One reader per sensor, shared by the conditions on it.
        self.readers = {t.when.sensor: reader(t.when.sensor, character)
                        for state in spec.states.values() for t in state.transitions
                        if t.when is not None}
        # state -> [(to, min steps in state, sensor reader or None, test on its value)]
        self.transitions = {
            name: [(t.to, round((t.after or 0.0) / dt),
                    self.readers[t.when.sensor] if t.when is not None else None,
                    compile_test(t.when) if t.when is not None else None)
                   for t in state.transitions]
            for name, state in spec.states.items()}
        # state -> (min steps in state before a sensor transition is polled, before a
        # timer-only transition fires): next_check is asked after every tick.
        self.first_due = {
            name: (min((a for _, a, s, _ in ts if s is not None), default=None),
                   min((a for _, a, s, _ in ts if s is None), default=None))
            for name, ts in self.transitions.items()}
        self.current = self.initial
        self.entered = 0

    def enter(self, name: str, now: int) -> None:
        self.current, self.entered = name, now

    def next_check(self, earliest: int) -> int | None:
        """The first step >= earliest at which a transition could fire."""
        polled, timer = self.first_due[self.current]
        best = None
        if polled is not None:
            at = self.entered + polled
            at = at if at > earliest else earliest
            best = -(-at // self.every) * self.every
        if timer is not None:
            at = self.entered + timer
            at = at if at > earliest else earliest
            best = at if best is None or at < best else best
        return best

    def due(self, now: int) -> str | None:
        """The state to go to now, if a transition fires (first listed wins). Sensors
        are polled on multiples of ``every``; conditions listed one after another on
        the same sensor share one reading."""
        polling = now % self.every == 0
        last = value = None
        for to, after, read, test in self.transitions[self.current]:
            if now < self.entered + after:
                continue
            if read is None:
                return to
            if polling:
                if read is not last:
                    value, last = read(), read
                if test(value):
                    return to
        return None

    def get_state(self) -> list:
        return [self.current, self.entered]

    def set_state(self, state) -> None:
        self.current, self.entered = state
