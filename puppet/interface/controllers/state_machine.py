"""State machines: which bindings and maps are live, and when to move on.

States are data (``states:`` and ``machines:`` in an interface); several machines run
side by side (one per limb, a gait machine beside a grasp machine). A key's ``goto``
or a transition on a timer or a sensor condition changes a machine's state; a
machine's ``any_state`` transitions hold in each of its states but the one they lead
to. Times are whole steps since entering, so a machine replays bit-identically and
its state is two plain values. Entering a state (running its ``enter`` action,
activating its maps) is the runtime's work: ``due`` only says where to go.
"""

from __future__ import annotations

import math

from puppet.interface.conditions import compile_bounds, compile_test, reader
from puppet.interface.ownership import Owner

# Sensors that change only when an input event comes (the device's inputs): a state whose
# polled conditions read nothing else need not poll again until one does.
DEVICE = ("input.mouse.", "input.pointer.", "input.gamepad.")


def _all_of(tests):
    """A reader that is 1.0 when every condition holds, else 0.0 (in order, so a cheap
    contact test written first spares the others). ``tests``: (reader, lo, hi, test):
    a range condition holds when lo < value < hi (compared here, not called: what its
    ``compile_test`` does), an ``is`` condition when ``test(value)``."""
    tests = tuple(tests)

    def read() -> float:
        for read_one, lo, hi, test in tests:
            if test is None:
                if not lo < read_one() < hi:
                    return 0.0
            elif not test(read_one()):
                return 0.0
        return 1.0
    return read


def _test_of(condition) -> tuple:
    """(lo, hi, None) for a range condition, (None, None, test) for an ``is``."""
    bounds = compile_bounds(condition)
    return (*bounds, None) if bounds is not None else (None, None, compile_test(condition))


class StateMachine:
    def __init__(self, name: str, machine, interface, character, dt: float,
                 channels: dict | None = None, inputs: dict | None = None):
        self.name = name
        self.channels = channels  # the runtime's input channels (``channel.NAME`` sensors)
        self.inputs = inputs  # the runtime's device inputs (``input.NAME`` sensors)
        self.spec = machine
        # Sensor conditions are polled at the control rate, on steps that are multiples
        # of ``every`` (absolute, so how advance() calls are split does not matter).
        self.every = max(1, round(1.0 / (interface.control_rate * dt)))
        self.initial = machine.start_state
        self.interface, self.character, self.dt = interface, character, dt
        self._tables: dict = {}  # role binding -> (transitions, first_due)
        # state -> per transition (in ``transitions`` order), the steps its `for` asks
        # its condition to have held (0: fires at once); ``_since``: when it began to
        self._holds = self._hold_steps()
        self._device_only = self._device_states()
        self._plans: dict = {}  # (state, binding's) -> (its transitions, _state_plan's)
        self.use_renamer(None, lambda sensor: sensor)
        self.current = self.initial
        self.entered = 0

    @property
    def has_quiet_states(self) -> bool:
        """Some state polls device inputs alone (``_device_states``): an input event
        must stir this machine (``InterfaceRuntime._stir``)."""
        return any(self._device_only.values())

    def use_renamer(self, binding, rename) -> None:
        """Read the sensors as role ``binding`` names them (``rename``: a sensor name
        with a role in it -> the one it means now)."""
        tables = self._tables.get(binding)
        if tables is None:
            tables = self._tables[binding] = self._compile(rename)
        self.transitions, self.first_due = tables
        self._now_in(self.__dict__.get("current", self.initial))

    def _now_in(self, state: str) -> None:
        """The current state's transitions and first due steps, looked up once per
        state change rather than at each poll (``due`` runs every control step); what
        they are for a state is worked out once per binding (``_state_plan``)."""
        key = (state, id(self.transitions))
        got = self._plans.get(key)
        if got is None or got[0] is not self.transitions:
            got = self._plans[key] = (self.transitions, self._state_plan(state))
        self._transitions, self._polled, self._timer, self._one_sensor, self._held = got[1]
        # a state polling device inputs alone (``_device_states``): after a poll that
        # found nothing, the next is at the next input event (``stir``) - ``quiet``
        self.device_only, self.quiet = self._device_only[state], False
        self._since = {}

    def prime(self) -> None:
        """Every state's plan under the binding of now (``_now_in``'s, made ahead)."""
        for state in self.spec.states:
            key = (state, id(self.transitions))
            if key not in self._plans:
                self._plans[key] = (self.transitions, self._state_plan(state))

    def _state_plan(self, state: str) -> tuple:
        """(transitions, first polled step, first timer step, ``_one_sensor``, the
        `for` steps) of ``state`` under the binding of now."""
        ts = self.transitions[state]
        polled, timer = self.first_due[state]
        # The commonest state (luxo-keys' upright, a gait's phases): every transition a
        # range condition on one sensor, from the moment the state is entered. ``due``
        # then reads that sensor and compares, nothing else: ``_one_sensor`` is the
        # reader and the (state to go to, lo, hi) in order.
        one = None
        held = self._holds[state]
        # (a state left only by `after: 0` timers has no sensor: the general loop's)
        if ts and ts[0][2] is not None and not any(held) and all(
                after == 0 and read is ts[0][2] and test is None
                for _, after, read, test, _, _ in ts):
            one = (ts[0][2], tuple((to, lo, hi) for to, _, _, _, lo, hi in ts))
        return ts, polled, timer, one, held

    def _hold_steps(self) -> dict[str, list[int]]:
        """Per state, each transition's `for` in steps, in the order ``_compile`` lists
        them (the state's own, then any_state's that lead elsewhere)."""
        name, machine, dt = self.name, self.spec, self.dt
        shared = list(machine.any_state.transitions)
        return {sname: [round((t.held or 0.0) / dt) for t in state.transitions]
                + [round((t.held or 0.0) / dt) for t in shared
                   if self.interface.resolve_goto(t.to, name) != (name, sname)]
                for sname, state in machine.states.items()}

    def _device_states(self) -> dict[str, bool]:
        """Per state: every transition it polls (its own, any_state's that lead
        elsewhere) reads device inputs alone (``DEVICE``), all from the same ``after``
        and none with a ``for``. Such a poll gives the same answer until an input event
        comes, so the machine skips the polls in between (the same steps fire)."""
        name, machine = self.name, self.spec
        shared = list(machine.any_state.transitions)
        found = {}
        for sname, state in machine.states.items():
            ts = [*state.transitions, *(t for t in shared
                                        if self.interface.resolve_goto(t.to, name)
                                        != (name, sname))]
            polled = [t for t in ts if t.conditions]
            found[sname] = bool(polled) and all(
                not t.held and all(c.sensor.startswith(DEVICE) for c in t.conditions)
                for t in polled) and len({round((t.after or 0.0) / self.dt)
                                          for t in polled}) == 1
        return found

    def _compile(self, rename):
        name, machine, interface, dt = self.name, self.spec, self.interface, self.dt
        shared = list(machine.any_state.transitions)
        readers = {c.sensor: reader(rename(c.sensor), self.character,
                                    self.channels, self.inputs)
                   for state in machine.states.values()
                   for t in [*state.transitions, *shared] for c in t.conditions}

        def compiled(t):
            conditions = t.conditions
            if len(conditions) > 1:  # all must hold: one reading of 1.0 or 0.0, which
                # holds when 0.5 < it (< inf): ``value > 0.5``, compared without a call
                return (interface.resolve_goto(t.to, name), round((t.after or 0.0) / dt),
                        _all_of([(readers[c.sensor], *_test_of(c)) for c in conditions]),
                        None, 0.5, math.inf)
            when = conditions[0] if conditions else None
            bounds = compile_bounds(when) if when is not None else None
            return (interface.resolve_goto(t.to, name), round((t.after or 0.0) / dt),
                    readers[when.sensor] if when is not None else None,
                    compile_test(when) if when is not None and bounds is None else None,
                    *(bounds or (None, None)))
        # state -> [((machine, to), min steps in state, sensor reader or None, test, lo,
        # hi)]: a sensor's test is lo < value < hi (compared here, not called) or, for
        # an ``is`` condition, the function ``test``; the state's own transitions first,
        # then any_state's that lead elsewhere
        transitions = {
            sname: [compiled(t) for t in state.transitions]
            + [compiled(t) for t in shared if interface.resolve_goto(t.to, name) != (name, sname)]
            for sname, state in machine.states.items()}
        # state -> (min steps in state before a sensor transition is polled, before a
        # timer-only transition fires): next_wakeup is asked after every tick.
        first_due = {
            sname: (min((a for _, a, s, *_ in ts if s is not None), default=None),
                    min((a for _, a, s, *_ in ts if s is None), default=None))
            for sname, ts in transitions.items()}
        return transitions, first_due

    def enter(self, state: str, now: int) -> None:
        self.current, self.entered = state, now
        self._now_in(state)

    def next_wakeup(self, earliest: int) -> int | None:
        """The first step >= earliest at which a transition could fire."""
        polled, timer = self._polled, self._timer
        best = None
        if polled is not None and not self.quiet:
            at = self.entered + polled
            at = at if at > earliest else earliest
            best = -(-at // self.every) * self.every
        if timer is not None:
            at = self.entered + timer
            at = at if at > earliest else earliest
            best = at if best is None or at < best else best
        return best

    def due(self, now: int) -> tuple[str, str] | None:
        """(machine, state) to go to now, if a transition fires (first listed wins).
        Sensors are polled on multiples of ``every``; conditions listed one after
        another on the same sensor share one reading. When none fires, ``wake_after``
        is ``next_wakeup(now + 1)`` (the arbiter's next schedule, without a call)."""
        if not self._transitions:  # a state left by keys alone (a climb's holds)
            self.wake_after = None
            return None
        every = self.every
        one = self._one_sensor
        if one is not None and not now % every:  # (see _now_in)
            value = one[0]()
            for to, lo, hi in one[1]:
                if lo < value < hi:
                    return to
            if self.device_only:  # the next poll after the next input event
                self.quiet = True
                self.wake_after = None
                return None
            self.wake_after = now + every  # the next poll: next_wakeup(now + 1)
            return None
        polling = now % every == 0
        last = value = None
        since = now - self.entered
        held = self._held
        for k, (to, after, read, test, lo, hi) in enumerate(self._transitions):
            if since < after:
                continue
            if read is None:
                return to
            if polling:
                if read is not last:
                    value, last = read(), read
                holds = (lo < value < hi) if test is None else test(value)
                if not held[k]:
                    if holds:
                        return to
                elif holds:  # `for`: held since the first poll that found it true
                    if now - self._since.setdefault(k, now) >= held[k]:
                        return to
                else:
                    self._since.pop(k, None)
        polled, timer = self._polled, self._timer
        if polling and self.device_only and since >= polled:
            self.quiet = True  # every polled transition asked: none until an input event
        # wake_after = self.next_wakeup(now + 1), inlined (the same arithmetic)
        earliest, entered, best = now + 1, self.entered, None
        if polled is not None and not self.quiet:
            at = entered + polled
            at = at if at > earliest else earliest
            best = -(-at // every) * every
        if timer is not None:
            at = entered + timer
            at = at if at > earliest else earliest
            best = at if best is None or at < best else best
        self.wake_after = best
        return None

    def owners(self) -> set[Owner]:
        return set()

    def get_state(self) -> list:
        if self._since:  # a `for` condition holding now: when each began, kept too
            return [self.current, self.entered, dict(self._since)]
        return [self.current, self.entered]

    def set_state(self, state) -> None:
        self.current, self.entered = state[0], state[1]
        self._now_in(self.current)
        if len(state) > 2:
            self._since = {int(k): v for k, v in state[2].items()}

    def stop(self) -> None:
        self.current, self.entered = self.initial, 0
        self._now_in(self.current)
