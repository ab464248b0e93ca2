"""Intentional contacts (Ishigaki et al. 2009), the tracker's part that swings a figure
held to a bar the way the performer's hands move about their centre of mass
(``tracking.contacts``). A mixin of ``Tracker``.

A contact is a grasp chain of ``contacts.hands`` that holds (the grasp's pin is
Ishigaki's joint at the hand). For each, r is the held point less the figure's centre
of mass, r^ the performer's hand less theirs (the effector channels, m from the centre
of mass). When the contact begins both are noted; then the swing PD pushes r's angle
toward its angle then plus r^'s turn since (``swing``) and r's turning rate toward
r^'s (``swing_damping``), and the linear spring r's length toward its length then
plus r^'s change (``spring``, ``damping``). The force (the PD's torque over |r| across
r, the spring's along it) is given to the centre of mass alone: every link the same
velocity change each control period. r^'s turning rate comes from the last two
samples (a stream's frames come at their own rate). Everything reads the figure, the
grasps and the channels: a replay does the same.
"""

from __future__ import annotations

import math

from pymunk._chipmunk_cffi import lib as _cp

_get_velocity, _set_velocity = _cp.cpBodyGetVelocity, _cp.cpBodySetVelocity


class IntentionalContacts:
    held_points = None  # () -> {chain: world point}: the runtime's grasps

    def _contacts_reset(self) -> None:
        self.contact: dict = {}  # chain -> [figure angle, length, performer's angle, length]
        self.perf_turn: dict = {}  # channel -> [angle, length, sample step, rate, rate of length]

    def _performer_vector(self, name: str):
        x, y = self.channels.get(name + ".x"), self.channels.get(name + ".y")
        if x is None or y is None:
            return None
        return math.atan2(y, x), math.hypot(x, y)

    def _contacts(self, step: int) -> None:
        spec = self.spec.contacts if self.spec is not None else None
        if spec is None or self.held_points is None:
            return
        held = self.held_points()
        for chain in [c for c in self.contact if c not in held]:
            del self.contact[chain]
        c = self.character
        mass = c.mass
        # the centre of mass and its velocity from one bulk reading of the bodies (the
        # same sums, in the same order, as body by body: the same bits)
        x, y = c.com()
        vx, vy = c.com_velocity()
        fx = fy = 0.0
        for chain, channel in spec.hands.items():
            if chain not in held:
                continue
            me = self._performer_vector(channel)
            if me is None:
                continue
            rate = self._performer_rate(channel, me, step)
            px, py = held[chain]
            rx, ry = px - x, py - y
            length = math.hypot(rx, ry)
            if length < 1e-6:
                continue
            angle = math.atan2(ry, rx)
            if chain not in self.contact:
                self.contact[chain] = [angle, length, me[0], me[1]]
            a0, l0, p0, q0 = self.contact[chain]
            ux, uy = -ry / length, rx / length  # r turned a quarter: where r's angle grows
            # r = held - com: the point fixed, r turns by d(angle) when the centre of mass
            # moves by -length * d(angle) along u
            turn = (-vx * ux - vy * uy) / length  # rad/s: r's turning rate
            want = a0 + math.remainder(me[0] - p0, 2 * math.pi)
            torque = spec.swing * math.remainder(want - angle, 2 * math.pi) + \
                spec.swing_damping * (rate[0] - turn)
            grow = (-vx * rx - vy * ry) / length  # m/s: r's length's rate
            pull = spec.spring * (l0 + me[1] - q0 - length) + spec.damping * (rate[1] - grow)
            # the torque turns r: a force -torque / length along u on the centre of mass;
            # a longer r wanted: the centre of mass pushed away from the hand (-r)
            fx += -torque / length * ux - pull * rx / length
            fy += -torque / length * uy - pull * ry / length
        if fx == 0.0 and fy == 0.0:
            return
        dvx, dvy = fx / mass * self.period, fy / mass * self.period
        get, set_ = _get_velocity, _set_velocity  # (what Body.velocity gets and sets)
        for body in c.bodies.values():
            cb = body._body
            v = get(cb)
            set_(cb, (v.x + dvx, v.y + dvy))

    def _performer_rate(self, channel: str, me, step: int):
        """(turning rate rad/s, length rate m/s) of the performer's vector, from the last
        two samples, held between them."""
        seen = self.perf_turn.get(channel)
        sample = self.last_sample
        if seen is None:
            self.perf_turn[channel] = [me[0], me[1], sample, 0.0, 0.0]
            return (0.0, 0.0)
        if sample > seen[2]:
            h = (sample - seen[2]) * self.dt
            seen[3] = math.remainder(me[0] - seen[0], 2 * math.pi) / h
            seen[4] = (me[1] - seen[1]) / h
            seen[0], seen[1], seen[2] = me[0], me[1], sample
        return (seen[3], seen[4])

    def contacts_state(self) -> list:
        return [{k: list(v) for k, v in self.contact.items()},
                {k: list(v) for k, v in self.perf_turn.items()}]

    def set_contacts_state(self, state) -> None:
        self._contacts_reset()
        if state is not None:
            self.contact = {k: list(v) for k, v in state[0].items()}
            self.perf_turn = {k: list(v) for k, v in state[1].items()}
