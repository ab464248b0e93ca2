"""Feedback: maps that read the figure's own sensors, and maps that add to a target.

A map may read a sensor (``sensor.com.vx``, ``sensor.angle.chest``: the figure's
state, in file units - degrees, m, m/s) instead of a device, so a designer can write
balance as data: foot placement from the centre of mass's offset and velocity
(SIMBICON's swing-hip rule, target = base + c_d * d + c_v * v), a trunk held upright.
Such maps run at the control rate (absolute multiples of the control period, so a
replay splits its steps any way and agrees).

Two writers of one joint combine only when the file says so: an ``add`` map's value
is added to the joint's target, whatever else writes that (a pose, a sequence, a
device map, a frame target), after they have written it. The order is documented:
every control step, first the frame targets are re-solved, then the sensor maps
that set targets write the joints they own, then the ``add`` maps add, in file order.
A sensor map that sets targets owns its joints from when it becomes active (its
mode or state is entered) until a later action takes them, like any map.
"""

from __future__ import annotations

from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import FEEDBACK, JointOwners, Owner
from puppet.physics.servo import GET_TARGET as _get_target
from puppet.physics.servo import SET_TARGET as _set_target


class Feedback:
    BUSY = "busy"

    def __init__(self, servos, owners: JointOwners, inputs: dict, every: int, sample=None):
        self.servos = servos
        # reads the sensors into the inputs (the character's ``sample``: at one instant)
        self.sample = sample or _read_each
        self.owners_table = owners
        self.inputs = inputs  # the runtime's input values; sensor readings are put here
        self.every = every
        self.readers: list[tuple[str, object]] = []  # (input name, reader)
        self.setters: list[tuple[object, tuple[str, ...]]] = []  # (applier, joints)
        self.adders: list = []  # contribution functions
        self.base: dict[str, float] = {}  # joint -> target before the additions
        self.last: dict[str, float] = {}  # joint -> target written (base + additions)
        self.busy = False  # maps to run, or additions still to take back

    def set_maps(self, readers, setters, adders) -> None:
        """The active feedback maps (the runtime's, on every mode or state change)."""
        self.readers, self.setters, self.adders = readers, setters, adders
        self.busy = bool(setters or adders or self.last)

    def claim(self, joints) -> None:
        self.owners_table.claim(joints, FEEDBACK)

    def tick(self, step: int) -> str | None:
        if step % self.every:
            return WAITED  # between control steps
        values = self.inputs
        self.sample(self.readers, values)
        table, servos = self.owners_table.table, self.servos
        for apply, joints in self.setters:
            owned = [j for j in joints if table.get(j) == FEEDBACK]
            if owned:
                others = [(servos[j], servos[j].target) for j in joints if j not in owned]
                apply(values)
                for servo, target in others:  # joints a later action took: left be
                    servo.target = target
        added: dict[str, float] = {}
        get = added.get
        for contribution in self.adders:
            for joint, value in contribution(values):
                added[joint] = get(joint, 0.0) + value
        base, last = self.base, self.last
        if len(last) > len(added) or any(j not in added for j in last):
            for joint in [j for j in last if j not in added]:  # an add map went inactive
                servo = servos[joint]
                if servo.target == last[joint]:
                    servo.target = base[joint]
                del base[joint], last[joint]
        get_last = last.get
        for joint, value in added.items():
            spring = servos[joint].spring._constraint  # (servo.target, read and written)
            now = _get_target(spring)
            was = get_last(joint)  # (a target is never None)
            b = base[joint] if was is not None and now == was else now  # rewritten?
            base[joint] = b
            last[joint] = target = b + value
            _set_target(spring, target)
        busy = self.busy = bool(self.setters or self.adders or last)
        if busy and self.every == 1:
            return WAITED  # at every step, still busy: the next wake-up is the next step,
        return None  # the arbiter's schedule (base.WAITED)

    def next_wakeup(self, earliest: int) -> int | None:
        if not (self.setters or self.adders or self.last):
            return None
        return -(-earliest // self.every) * self.every

    def owners(self) -> set[Owner]:
        return {FEEDBACK} if self.setters else set()

    def get_state(self):
        return [dict(self.base), dict(self.last)]

    def set_state(self, state) -> None:
        self.base, self.last = dict(state[0]), dict(state[1])
        self.busy = bool(self.setters or self.adders or self.last)

    def adopt(self, old: Feedback, same, now: int) -> set[Owner]:
        self.base, self.last = dict(old.base), dict(old.last)
        self.busy = bool(self.setters or self.adders or self.last)
        return {FEEDBACK}

    def stop(self) -> None:
        self.base, self.last = {}, {}
        self.busy = bool(self.setters or self.adders)


def _read_each(readers, values: dict) -> None:
    for name, read in readers:
        values[name] = read()
