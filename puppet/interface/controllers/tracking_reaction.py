"""Impact reactions of KD control (Oshita 2006), the tracker's part that judges a push and
weakens the pulls: small (a dip), large (a protective step), fall (the pulls let go; a
get-up follows when the interface has one, ``tracking_getup``). A mixin of ``Tracker``:
it reads the tracker's spec, character and state."""

from __future__ import annotations

import math


class Reactions:
    def _react(self, step: int, performed_com, performed_vx: float) -> None:
        """Judge the push just taken and start its reaction. The extrapolated centre
        of mass (xcom = x + v sqrt(l / g)) is measured against the support - the feet's
        contacts, widened to the performance's own xcom, since a walking performer's
        lies ahead of their feet and a step catches it: inside (or within
        ``small_margin``), small; beyond by up to ``step_margin``, large; further, a
        fall."""
        from puppet.physics.balance import balance

        c = self.character
        space = c.bodies[c.spec.root].space
        gravity = tuple(space.gravity) if space is not None else (0.0, -9.81)
        b = balance(c, gravity, self.ground_at or (lambda x: None))
        r = self.spec.reaction
        if b.support is None:
            beyond = r.step_margin  # in the air: not a fall yet
        else:
            g = math.hypot(*gravity) or 9.81
            height = max(1e-3, performed_com[1] - b.ground_y)
            mine = performed_com[0] + performed_vx * math.sqrt(height / g)
            lo, hi = min(b.support[0], mine), max(b.support[1], mine)
            beyond = max(lo - b.xcom, b.xcom - hi, 0.0)
        case = ("small" if beyond <= r.small_margin else
                "large" if beyond <= r.step_margin else "fall")
        self.reaction = (case, step)
        self.impact_at = None
        self.step = None
        self.search_at = self.lib = None
        if self._library_case(case):  # Zordan's search, not a protective step
            self._schedule_search(step)
            return
        if case == "large" and self.soles and b.support is not None and beyond > 0:
            self.step = self._protective_step(step, b, 1.0 if b.xcom > b.support[1]
                                              else -1.0)

    def _protective_step(self, step: int, b, way: float) -> list:
        """[foot, start step, from x, from y, to x, to y]: the foot off the ground (else
        the one behind, going ``way``) steps to just past the extrapolated centre of
        mass (Oshita's protective step), its centre of mass where a flat foot's is."""
        c, r = self.character, self.spec.reaction
        feet = list(self.soles)
        free = [f for f in feet if not c.in_contact(f)]
        foot = free[0] if free else min(feet, key=lambda f: way * c.link_position(f)[0])
        x0, y0 = c.link_position(foot)
        x1 = b.xcom + way * r.step_past
        ground = self.ground_at(x1) if self.ground_at is not None else None
        y1 = (ground if ground is not None else b.ground_y) + c.bodies[foot].center_of_gravity[1]
        return [foot, step, x0, y0, x1, y1]

    def _weight(self, step: int) -> float:
        """How much of the pulls acts now (1 without a reaction)."""
        if self.reaction is None:
            return 1.0
        case, start = self.reaction
        spec = getattr(self.spec.reaction, case)
        if self.lib is not None or self.search_at is not None:  # a library window's
            return self._library_weight(step, spec.weight)
        t = (step - start) * self.dt
        if t < spec.hold:
            return spec.weight
        if case == "fall" and self.spec.reaction.get_up is not None:
            return 1.0  # getting up (_pull starts it): the pulls whole, but no lifting
        t -= spec.hold
        if t >= spec.recover:
            self.reaction = self.step = None
            return 1.0
        return spec.weight + (1.0 - spec.weight) * t / spec.recover

    def _stepped(self, step: int, weight: float, px: float, py: float):
        """The stepping foot's target: along the step (lifted in the middle), then held
        where it landed, and blended back to the performance (``px``, ``py``) as the
        pulls come back."""
        foot, start, x0, y0, x1, y1 = self.step
        r = self.spec.reaction
        u = min(1.0, (step - start) * self.dt / r.step_time)
        sx = x0 + (x1 - x0) * u
        sy = y0 + (y1 - y0) * u + r.step_lift * math.sin(math.pi * u)
        low = r.large.weight
        back = 0.0 if weight <= low else (weight - low) / (1.0 - low)
        return sx + (px - sx) * back, sy + (py - sy) * back

