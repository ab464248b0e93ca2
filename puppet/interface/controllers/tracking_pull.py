"""KD tracking's pulls (``Tracker._pull``): each link's centre of mass pulled toward
the performed pose's, as a velocity change each control step. A mixin of ``Tracker``.

Two paths give the same bits: the compiled kernel's (``physics.kernel``, through
``kd_kernel``) when it is built, and the Python below it, which is the reference the
kernel's C follows operation for operation (``PUPPET_KERNEL=python`` runs it).
"""

from __future__ import annotations

import math

from pymunk._chipmunk_cffi import lib as _cp

from puppet.interface.controllers.kd_kernel import Kept, TrackKernel
from puppet.interface.controllers.kd_pull import (
    channel_pose,
    link_plan,
    lowest_points,
    tracked_chain,
)
from puppet.interface.controllers.tracking_getup import supported
from puppet.interface.ownership import Owner
from puppet.physics import kernel as _kernel

TRACK = Owner("track")
PRESS = 0.003  # m: the placed pose puts its lowest foot this far into the ground, so
# the foot stands on it (a sole held exactly at the surface makes no contact)


def velocity_sample(tr, t) -> tuple[int, float]:
    """The performed velocities at the tracker's last sample, as ``pk_track_pose``
    takes them: (0, 0.0) the same sample as before, (1, h) a difference over h s from
    the previous one, (2, 0.0) none to difference (the first, or after a rewind); the
    sample then becomes the previous one (the pull's tick and the poll loop's)."""
    sample = tr.last_sample
    vel, h = 0, 0.0
    if not t.has_prev or sample != tr.prev_step:
        if t.has_prev and sample > tr.prev_step:
            vel, h = 1, (sample - tr.prev_step) * tr.dt
        else:
            vel = 2
        tr.prev_step = sample
    return vel, h


class Pulls:
    # the performed link positions at the last sample, their velocities from the two
    # last samples and the feet's turning rates: in the kernel's arrays when it runs
    prev = Kept("prev")
    vel = Kept("vel")
    spin = Kept("spin")

    def _pulls_init(self) -> None:
        """The kernel's arrays (before anything sets ``prev``), or None: Python's path."""
        self._kern = None
        self._kernel_tick = None  # (step, view, values, has): _kernel_values's
        if self.spec is not None and self.spec.root is not None:  # (pulls to make)
            k = _kernel.get()
            if k is not None:
                self._kern = TrackKernel(k, self, self._all_points)

    def _tracked_rows(self) -> list[tuple]:
        tracked = self.__dict__.get("_tracked")
        if tracked is None:
            tracked = self._tracked = tracked_chain(self._chain, self.joints, self.limits)
        return tracked

    def _kernel_values(self, kern, step: int, ch: dict, fresh: bool = False):
        """The kernel bound to the figure as it is, and ``ch``'s values in the order it
        reads them (``kern.names``) with which it has (None: all): read by the targets
        (``fresh``) and again by the pulls of the same tick for the same view."""
        got = self._kernel_tick
        if not fresh and got is not None and got[0] == step and got[1] is ch:
            return got[2], got[3]
        c = self.character
        if kern.bodies_of is not c.bodies:  # (a restore binds new bodies and springs)
            kern.bind(self._link_plan(self._figure.rows()), c.servos)
            kern.bodies_of = c.bodies
        vals, has = list(map(ch.get, kern.names)), None
        if None in vals:
            has = bytes(v is not None for v in vals)
            vals = [0.0 if v is None else v for v in vals]
        self._kernel_tick = (step, ch, vals, has)
        return vals, has

    def _owned(self, table, joints, cache: str):
        """None when the tracker holds every joint of ``joints`` (None: a link with no
        joint above), else a byte per joint: 1 where it does."""
        owners = list(map(table.get, joints))
        every = self.__dict__.get(cache)
        if every is None:
            every = self.__dict__[cache] = [None if j is None else TRACK for j in joints]
        if owners == every:
            return None
        return bytes(j is None or o == TRACK for j, o in zip(joints, owners))

    def _write_targets_kernel(self, kern, step: int, channels: dict) -> None:
        """``_write_targets`` without a blend, by the kernel."""
        vals, has = self._kernel_values(kern, step, channels, fresh=True)
        own = self._owned(self.owners_table.table, kern.target_joints, "_every_target")
        kern.lib.pk_targets(kern.t, vals, has or kern.kernel.ffi.NULL,
                            own or kern.kernel.ffi.NULL)

    def _pull(self, step: int, channels: dict | None = None) -> None:
        """Velocity changes that pull each link's centre of mass toward the performed
        pose's (implicit PD over one control period), weaker while reacting to a push.
        ``channels``: this step's view, when the targets were just written from it."""
        reaction = self.reaction
        if reaction is not None and reaction[0] == "fall" and self.getup is None \
                and self.spec.reaction.get_up is not None and self.lib is None \
                and self.search_at is None \
                and (step - reaction[1]) * self.dt >= self.spec.reaction.fall.hold:
            self._start_get_up(step)  # lain long enough: up, through the poses
            channels = None  # the view is the get-up's now
        spec = self.spec
        ch = self._view(step) if channels is None else channels
        root = spec.root
        x, y, a = ch.get(root.x), ch.get(root.y), ch.get(root.angle)
        if x is None or y is None or a is None:
            return
        if self.x0 is None:
            self.x0 = self._hinge_world()[0] - x
        kern = self._kern
        if kern is None:
            self._pull_python(step, ch, x, y, a)
        else:
            self._pull_kernel(kern, step, ch, x, a)

    def _pull_kernel(self, kern, step: int, ch: dict, x, a) -> None:
        """``_pull_python``'s work by the kernel, the rare parts in Python."""
        c, ffi, lib = self.character, kern.kernel.ffi, kern.lib
        vals, has = self._kernel_values(kern, step, ch)
        getting_up = self.getup is not None
        soles = self._all_points() if getting_up else self.soles
        lift, ground, extra = 0, 0.0, 0.0
        if soles and self.ground_at is not None:
            ground = self.ground_at(self.x0 + x)
            if ground is None:
                ground = 0.0
            else:
                lift = 2 if getting_up else 1
                clearance = ch.get(self.spec.root.clearance, 0.0)
                extra = clearance if clearance > 0.0 else -PRESS
        t = kern.t
        vel, h = velocity_sample(self, t)
        lib.pk_track_pose(t, vals, has or ffi.NULL, vals[0], vals[1], vals[2], self.x0,
                          lift, ground, extra, vel, h)
        if self.impact_at is not None and step > self.impact_at:
            self._react_to(step, kern.targets(), self.vel)
        weight = self._weight(step) * self._blend(step)
        stepping, sx, sy = -1, 0.0, 0.0
        if self.step is not None:
            stepping = kern.row_of[self.step[0]]
            tg = kern.t.targets
            sx, sy = self._stepped(step, weight, tg[3 * stepping], tg[3 * stepping + 1])
        no_lift, rise = False, 0.0
        if getting_up:
            get_up = self.spec.reaction.get_up
            no_lift = not supported(c, self.soles, get_up.hands)  # nothing pushes on the
            rise = get_up.rise  # ground
        own = self._owned(self.owners_table.table, kern.row_joints, "_every_row")
        lib.pk_track_pull(t, weight, own or ffi.NULL, stepping, sx, sy, getting_up,
                          no_lift, rise, self.period)

    def _react_to(self, step: int, targets: dict, vel: dict) -> None:
        """Judge the push taken (``_react``) from the performed pose's centre of mass
        and velocity."""
        c = self.character
        mass = c.mass
        com = (sum(c.bodies[n].mass * p[0] for n, p in targets.items()) / mass,
               sum(c.bodies[n].mass * p[1] for n, p in targets.items()) / mass)
        vx = sum(c.bodies[n].mass * v[0] for n, v in vel.items()) / mass
        self._react(step, com, vx)

    def _pull_python(self, step: int, ch: dict, x, y, a) -> None:
        """``_pull``'s work in Python (the kernel's reference)."""
        spec, c = self.spec, self.character
        root = spec.root
        angle = math.radians(a)
        hinges = self.__dict__.setdefault("_hinges", {})  # (a search of the joints)
        hinge = hinges.get(root.at) or hinges.setdefault(root.at, c.spec.joint(root.at).anchor)
        cos, sin = math.cos(angle), math.sin(angle)
        hx, hy = self.x0 + x, y
        origin = (hx - (cos * hinge[0] - sin * hinge[1]), hy - (sin * hinge[0] + cos * hinge[1]))
        # the performed pose, each link's turn's cosine and sine with it (kd_pull)
        tracked = self._tracked_rows()
        poses = channel_pose(tracked, c.spec.root, origin, angle, cos, sin, ch)
        lift = self._lift(poses, hx, ch.get(root.clearance, 0.0),
                          self._all_points() if self.getup is not None else self.soles)
        T = self.period
        prev = self.prev
        plan = self._link_plan(self._figure.rows())
        targets = {}
        for name, _, _, _, gx, gy, _, _, _, _, sole in plan:
            ox, oy, oa, cl, sl = poses[name]
            if sole:  # the feet's performed angles ride along
                targets[name] = (ox + cl * gx - sl * gy, oy + sl * gx + cl * gy + lift, oa)
            else:
                targets[name] = (ox + cl * gx - sl * gy, oy + sl * gx + cl * gy + lift)
        # The performed velocities, from the last two samples (a stream's frames come
        # at their own rate, not the control rate's): held between samples.
        sample = self.last_sample
        if prev is None or sample != self.prev_step:
            if prev is not None and sample > self.prev_step:
                h = (sample - self.prev_step) * self.dt
                self.vel = {n: ((p[0] - prev[n][0]) / h, (p[1] - prev[n][1]) / h)
                            for n, p in targets.items() if n in prev}
                self.spin = {n: (targets[n][2] - prev[n][2]) / h for n in self.soles
                             if n in prev and len(prev[n]) > 2}
            else:
                self.vel, self.spin = {}, {}
            self.prev, self.prev_step = targets, sample
        vel = self.vel
        if self.impact_at is not None and step > self.impact_at:
            self._react_to(step, targets, vel)
        weight = self._weight(step) * self._blend(step)
        stepping = self.step[0] if self.step is not None else None
        getting_up = self.getup is not None
        if getting_up:
            get_up = self.spec.reaction.get_up
            no_lift = not supported(c, self.soles, get_up.hands)  # nothing pushes on the ground
            rise = get_up.rise
        table, spins = self.owners_table.table, self.spin
        state = self._figure.read()  # every body in one call: what each link is now
        set_velocity, set_spin = _cp.cpBodySetVelocity, _cp.cpBodySetAngularVelocity
        mcos, msin, still = _kernel.cos, _kernel.sin, (0.0, 0.0)  # (C's answers on a
        # blown-up state, as the kernel's; hoisted: 13 links at 120 Hz)
        for name, cb, i, m, gx, gy, joint, ks, ds, m_T, sole in plan:
            if joint is not None and table.get(joint) != TRACK:
                continue  # a link the performer does not drive (a key took its joint)
            target = targets[name]
            px, py = target[0], target[1]
            w = weight
            if name == stepping:  # the protective step, then back to the performance
                px, py = self._stepped(step, weight, px, py)
                w = 1.0
            k, d = ks * w, ds * w  # kp * s * w, dp * sqrt(s) * w: the same ratio
            if k == 0.0 and d == 0.0:
                continue
            tvx, tvy = vel.get(name, still)
            bx, by, ba, vx, vy, spin = state[i:i + 6]
            cb_, sb = mcos(ba), msin(ba)  # its centre: cpBodyLocalToWorld's sums
            wx, wy = cb_ * gx + -sb * gy + bx, sb * gx + cb_ * gy + by
            den = m_T + k * T + d
            new_vy = (m * vy / T + k * (py - wy) + d * tvy) / den
            if getting_up and new_vy > vy:  # no levitation: a link rises only by pushing
                new_vy = vy if no_lift else min(new_vy, max(vy, rise))  # on the ground,
                # and no faster than a body pushes itself up
            set_velocity(cb, ((m * vx / T + k * (px - wx) + d * tvx) / den, new_vy))
            if sole:  # a foot is also turned flat as performed (its sole
                # stands on the ground; the ankle's inertia-scaled gain alone is weak)
                inertia = c.bodies[name].moment
                kt, dt_ = k * inertia / m, d * inertia / m  # the same natural frequency
                want = poses[name][2]
                turn = want - ba
                turn -= 2 * math.pi * _kernel.nearest(turn / (2 * math.pi))
                set_spin(cb, (inertia * spin / T + kt * turn + dt_ * spins.get(name, 0.0))
                         / (inertia / T + kt * T + dt_))

    def _link_plan(self, rows) -> list[tuple]:
        """``kd_pull.link_plan`` of ``rows``, again for new rows (a restore re-binds the
        bodies)."""
        cached = self.__dict__.get("_plan")
        if cached is None or cached[0] is not rows:
            cached = self._plan = (rows, link_plan(rows, self.spec.preset, self.scale,
                                                   self.joint_of, self.period, self.soles))
        return cached[1]

    def _all_points(self) -> dict:
        """Every link's lowest points (a get-up's pose stands on knees, hands...)."""
        if not hasattr(self, "_every_point"):
            c = self.character
            self._every_point = {link.name: lowest_points(c, link.name)
                                 for link in c.spec.links}
        return self._every_point

    def _lift(self, poses, x: float, clearance: float, soles=None) -> float:
        """How far up (or down) the performed pose must go for its lowest foot to stand
        on the ground - or to be ``clearance`` above it, in a performer's jump: the
        performer's proportions differ from the figure's, and a foot held in the air by
        the pulls would leave the figure hanging on them."""
        soles = self.soles if soles is None else soles
        if not soles or self.ground_at is None:
            return 0.0
        ground = self.ground_at(x)
        if ground is None:
            return 0.0
        lowest = math.inf
        for link, points in soles.items():
            _, oy, _, cl, sl = poses[link]  # (performed_pose: its cosine and sine)
            for px, py, r in points:
                y = oy + sl * px + cl * py - r
                if y < lowest:
                    lowest = y
        return ground + (clearance if clearance > 0.0 else -PRESS) - lowest
