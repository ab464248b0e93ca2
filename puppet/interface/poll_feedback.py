"""Feedback's add maps in the kernel's stepping loop (``interface.poll_plan``).

A state's sensor maps that add to targets (``combine: add``: a landing's ankle held
by the base's angle and spin, a tuck opened by the fall time) run at every control
step: ``Feedback.tick`` samples their sensors into the runtime's inputs, sums each
joint's terms in file order (``maps.compile_contribution``) and adds the sum to the
joint's base (the target before the additions; a target rewritten since the last
write is the new base). ``pk_poll`` does the same between Python's ticks, when every
active feedback map is such an add map with a linear curve on a sensor it reads (or
a constant ``add:``); the inputs, bases and last writes are handed back after each
call, so a snapshot, a later tick or the HUD find what Python would have left.
"""

from __future__ import annotations

import math

# a sensor a feedback map reads -> pk_poll's code (see poll_plan.condition_kind)
_DEGREES = 180.0 / math.pi  # map_reader's angle unit: ``read() * k``


class FeedbackPlan:
    """The add maps' part of a ``PollPlan``'s table (one runtime)."""

    def __init__(self, plan, n: int):
        self.plan = plan
        ffi, p = plan.ffi, plan.plan
        keep = plan._keep
        ints = [ffi.new("int[]", n) for _ in range(5)]
        ptrs = [ffi.new("void *[]", n) for _ in range(3)]
        doubles = [ffi.new("double[]", n) for _ in range(11)]
        keep += ints + ptrs + doubles
        p.r_kind, p.a_read, p.a_joint, p.a_clamp, p.f_has = ints
        p.r_a, p.r_b, p.f_spring = ptrs
        (p.r_scale, p.sampled, p.a_x0, p.a_inv, p.a_lo, p.a_span, p.a_gain, p.f_base,
         p.f_last, p.f_sum, _) = doubles
        self.n = n
        self._for = None  # the feedback adders the table was made for (their identity)
        self.table = None  # (reader names, their sensors' (code, name, scale), terms, joints)

    def current(self, rt):
        """The active feedback maps as ``pk_poll`` runs them, or None when one is not
        an add map it can run (a set map, a curve, a device input, another sensor)."""
        fb = rt.feedback
        if fb.adders is self._for:
            return self.table
        from puppet.interface.poll_plan import condition_kind

        self._for, self.table = fb.adders, None
        if fb.setters:
            return None
        root = rt.character.spec.root
        names = [name for name, _ in fb.readers]
        sensors = []
        for name in names:
            kind = condition_kind(name[len("sensor."):], root)
            if kind is None or kind[0] == 0:  # (a contact is not a map's input)
                return None
            angle = kind[0] in (1, 2, 3)
            sensors.append((*kind, _DEGREES if angle else 0.0))
        terms, joints = [], []
        for m in rt.active_maps:
            if not m.feedback:
                continue
            m = rt.roles.map(m)
            if getattr(m, "combine", "set") != "add":
                return None
            gains = list(m.gains().items())
            for joint, _ in gains:
                if joint not in joints:
                    joints.append(joint)
            if m.add is not None:  # compile_contribution's constant
                terms += [(-1, joints.index(j), 0, 0.0, 0.0, 0.0, 0.0, g * math.radians(m.add))
                          for j, g in gains]
                continue
            if m.curve != "linear" or m.input not in names:
                return None
            (x0, x1), (y0, y1) = m.from_, m.to
            inv, lo, span = 1.0 / (x1 - x0), math.radians(y0), math.radians(y1 - y0)
            terms += [(names.index(m.input), joints.index(j), int(bool(m.clamp)), x0, inv,
                       lo, span, g) for j, g in gains]
        if len(terms) > self.n or len(joints) > self.n or len(names) > self.n:
            return None
        self.table = (names, sensors, terms, joints)
        return self.table

    def fill(self, rt, table) -> None:
        """Write the table's sensors, terms and joints (bodies and springs as they are
        now)."""
        plan, p = self.plan, self.plan.plan
        names, sensors, terms, joints = table
        bodies, spec = rt.character.bodies, rt.character.spec
        for r, (kind, name, scale) in enumerate(sensors):
            a = b = plan.ffi.NULL
            if kind == 2:
                joint = spec.joint(name)
                a, b = plan.pointer(bodies[joint.child]._body), \
                    plan.pointer(bodies[joint.parent]._body)
            elif name is not None:
                a = plan.pointer(bodies[name]._body)
            p.r_kind[r], p.r_a[r], p.r_b[r], p.r_scale[r] = kind, a, b, scale
        for t, (read, joint, clamp, x0, inv, lo, span, gain) in enumerate(terms):
            p.a_read[t], p.a_joint[t], p.a_clamp[t] = read, joint, clamp
            p.a_x0[t], p.a_inv[t], p.a_lo[t], p.a_span[t], p.a_gain[t] = x0, inv, lo, span, gain
        servos = rt.character.servos
        for j, joint in enumerate(joints):
            p.f_spring[j] = plan.pointer(servos[joint].spring._constraint)
        p.n_read, p.n_add, p.n_fb = len(sensors), len(terms), len(joints)

    def refresh(self, rt, table) -> bool:
        """The bases and last writes as Feedback has them now (and the gravity); False
        when a joint's last write is one these maps do not make (an add map gone:
        Python's tick takes it back first)."""
        p, fb = self.plan.plan, rt.feedback
        base, last = fb.bases()
        joints = table[3]
        if len(last) > len(joints) or any(j not in joints for j in last):
            return False
        for j, joint in enumerate(joints):
            was = last.get(joint)
            p.f_has[j] = was is not None
            if was is not None:
                p.f_last[j], p.f_base[j] = was, base[joint]
        return True

    def hand_back(self, rt, table) -> None:
        """After a call that ran the maps: the sensors' last readings into the inputs,
        each joint's base and last write into Feedback (as its tick leaves them)."""
        p, fb, inputs = self.plan.plan, rt.feedback, rt.inputs
        names, _, _, joints = table
        for r, name in enumerate(names):
            inputs[name] = p.sampled[r]
        base, last = fb.bases()
        for j, joint in enumerate(joints):
            base[joint], last[joint] = p.f_base[j], p.f_last[j]
