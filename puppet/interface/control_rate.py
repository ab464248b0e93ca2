"""The control period: how many physics steps apart the control steps are, per state.

A control step is a step at which the state machines test their sensor conditions, the
frame targets (world angles) are re-solved, the sensor maps are worked out and the
targets of a pose or set with ``over`` move on. The interface's ``control_rate`` (60 a
second by default: every 8th step at 1/480 s) sets it; a state's own ``control_rate``
makes it faster while that state is active (a take-off, a flight, a landing: a phase
that must switch on its sensors at once), in every machine, then back to the
interface's. The period follows from which states are active, the state machines'
saved state, so a checkpoint or a rewind restores it exactly. Control steps are the
steps that are multiples of the period (absolute, as before), so a period of 1 is every
step and a period of 8 the next multiple of 8 after the fast state ends.
"""

from __future__ import annotations


def control_period(rate: float, dt: float) -> int:
    """Steps between control steps at ``rate`` (Hz) on a ``dt`` step (at least 1)."""
    return max(1, round(1.0 / (rate * dt)))


class ControlPeriod:
    """The period now: the interface's, or the shortest a current state asks for."""

    def __init__(self, spec, machines: dict, dt: float):
        self.base = self.every = control_period(spec.control_rate, dt)
        fast = {}
        for name, machine in machines.items():
            periods = {state: control_period(s.control_rate, dt)
                       for state, s in machine.states.items() if s.control_rate is not None}
            periods = {state: p for state, p in periods.items() if p < self.base}
            if periods:
                fast[name] = periods
        # machine -> state -> its period (only the states faster than the interface)
        self.fast: dict[str, dict[str, int]] = fast

    def now(self, machines: dict) -> int:
        """The period while ``machines`` (name -> StateMachine) are in their current
        states."""
        every = self.base
        for name, periods in self.fast.items():
            p = periods.get(machines[name].current)
            if p is not None and p < every:
                every = p
        return every
