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
from puppet.interface.controllers.feedback_kernel import FeedbackKernel
from puppet.interface.ownership import FEEDBACK, JointOwners, Owner
from puppet.physics import kernel as _kernel
from puppet.physics.servo import GET_TARGET as _get_target
from puppet.physics.servo import SET_TARGET as _set_target


class Feedback:
    BUSY = "busy"

    def __init__(self, servos, owners: JointOwners, inputs: dict, every: int, sample=None,
                 character=None):
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
        # the compiled call (feedback_kernel): the add maps and their sensors in C, for
        # the active maps when they are all its (``_plan``); while it runs (``_in_c``)
        # base and last are its arrays', made into the dicts again by ``_pull``
        kern = _kernel.get() if character is not None else None
        self._fk = None if kern is None else FeedbackKernel(kern, character, servos)
        self._plan = None
        self._in_c = False
        # a step whose add the kernel's loop made before entries it left to Python's
        # tick there (interface.poll_feed): that tick does not add again
        self.done_at = -1

    def set_maps(self, readers, setters, adders) -> None:
        """The active feedback maps (the runtime's, on every mode or state change)."""
        if readers is not self.readers or setters is not self.setters \
                or adders is not self.adders:  # (the same maps: the same plan, kept)
            self.readers, self.setters, self.adders = readers, setters, adders
            fk = self._fk
            self._plan = None if fk is None or setters or not adders \
                else fk.plan(readers, adders)
        if self._plan is None:  # (else the kernel's arrays stay what base and last are)
            self._pull()
        self.busy = bool(setters or adders or self.last)

    def compiled(self):
        """The compiled call's struct (``pk_feedback``) for the kernel's stepping loop
        (``interface.poll_plan``) to run this feedback's ticks with, base and last in its
        arrays; None when a tick needs Python (a map or a sensor not the kernel's)."""
        plan = self._plan
        f = None if plan is None else self._fk.for_loop(plan)
        if f is not None and not self._in_c:
            self._fk.push(self.base, self.last)
            self._in_c = True
        return f

    def ran(self) -> None:
        """After the stepping loop ran ticks with ``compiled``: their sensors' last
        readings into the inputs."""
        self._fk.hand_back(self._plan, self.inputs)

    def _pull(self) -> None:
        """base and last from the compiled call's arrays, where they are kept now."""
        if self._in_c:
            self.base, self.last = self._fk.pull()
            self._in_c = False

    def claim(self, joints) -> None:
        self.owners_table.claim(joints, FEEDBACK)

    def tick(self, step: int) -> str | None:
        if step % self.every:
            return WAITED  # between control steps
        if step == self.done_at:  # (made in the kernel's loop: poll_feed.fed_back)
            self.done_at = -1
            return None
        plan = self._plan
        if plan is not None:  # the compiled call: the rest of this tick, in C
            if not self._in_c:
                self._fk.push(self.base, self.last)
                self._in_c = True
            self._fk.tick(plan, self.inputs, self.sample)
            self.busy = True
            return WAITED if self.every == 1 else None
        self._pull()
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
        self._pull()
        return [dict(self.base), dict(self.last)]

    def set_state(self, state) -> None:
        self._in_c = False
        self.done_at = -1
        self.base, self.last = dict(state[0]), dict(state[1])
        self.busy = bool(self.setters or self.adders or self.last)

    def adopt(self, old: Feedback, same, now: int) -> set[Owner]:
        old._pull()
        self._in_c = False
        self.base, self.last = dict(old.base), dict(old.last)
        self.busy = bool(self.setters or self.adders or self.last)
        return {FEEDBACK}

    def stop(self) -> None:
        self._in_c = False
        self.base, self.last = {}, {}
        self.busy = bool(self.setters or self.adders)


def _read_each(readers, values: dict) -> None:
    for name, read in readers:
        values[name] = read()
