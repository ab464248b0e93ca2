"""Tracking a performance: mocap channels drive the figure (``tracking:`` section).

``angles``: each tracked joint's target is its channel's angle (clamped to the joint's
limits). ``kd`` (Nguyen et al. 2010): the same targets with inertia-scaled gains, and
Cartesian PD pulls of each link's centre of mass toward where the performed pose -
the root channels placing the root joint's hinge, the joint channels bending the rest
- puts it, scaled by ``scale`` (feet strongest, for balance). Three deliberate changes
from the paper's ``u = kp (p* - p) - dp v``: the damping acts on the velocity relative
to the performed one (a walking target is followed without drag), a link's ``scale``
multiplies kp and its square root dp (the damping ratio stays the paper's; a foot
damped 125x would lag the performance by a fifth of a second), and the pull is
integrated implicitly (backward Euler, as a velocity change each control step), so a
foot's 125x gain stays stable at any control rate.

Tracking is an action like any other: a later action that takes a tracked joint
takes it whole - its target, its gains back from KD's, and the pull on the link below
it.

Everything runs on absolute multiples of the control period and reads only the
channels, the figure's state and its own plain state, so a replay (or a restored
checkpoint) does the same to the bit. A stream with no sample for ``lost_after`` s is
lost: the tracker lets go of its joints (and the figure's gains go back) until samples
come again, when it takes its joints back as a new action would.
"""

from __future__ import annotations

import math

from pymunk._chipmunk_cffi import lib as _cp

from puppet.data.tracking import TrackingSpec
from puppet.interface.ownership import JointOwners, Owner
from puppet.physics.body_state import BodyReader
from puppet.physics.kinematics import beyond, joint_order

TRACK = Owner("track")
OFF, ANGLES, KD = "off", "angles", "kd"
PRESS = 0.003  # m: the placed pose puts its lowest foot this far into the ground, so
# the foot stands on it (a sole held exactly at the surface makes no contact)


class Tracker:
    BUSY = "busy"

    def __init__(self, spec: TrackingSpec | None, character, owners: JointOwners,
                 channels: dict, every: int, dt: float, restore_gains, ground_at=None):
        self.spec = spec
        self.character = character
        self.owners_table = owners
        self.channels = channels  # the runtime's channel values, by bare name
        self.every = every
        self.period = every * dt
        self.dt = dt
        self.restore_gains = restore_gains  # puts the interface's gains back
        self.lost_steps = 0 if spec is None else max(1, round(spec.lost_after / dt))
        cs = character.spec
        self.order = joint_order(cs)
        # the joints root outward as plain values, for the performed pose (``_performed``)
        self._chain = [(j.name, j.parent, j.child, j.anchor[0], j.anchor[1])
                       for j in self.order]
        self._reader = BodyReader()  # the figure in one call (KD pulls)
        self.limits = {j.name: (None if j.limits is None else
                                (math.radians(j.limits[0]), math.radians(j.limits[1])))
                       for j in cs.actuated}
        self.joints: dict[str, str] = {}  # tracked joint -> its channel
        if spec is not None:
            names = [j.name for j in cs.actuated] if spec.joints == "all" else spec.joints
            self.joints = {j: spec.channels.get(j, j) for j in names}
        self.inertia = {j: _inertia_beyond(character, j) for j in self.joints}
        self.pulled = [link.name for link in cs.links]
        self.joint_of = {j.child: j.name for j in cs.joints}  # link -> the joint above it
        self.scale = {} if spec is None else dict(spec.scale)
        self.ground_at = ground_at  # x -> the ground's surface height (None: no lift)
        self.soles = {} if spec is None else {f: _lowest_points(character, f) for f in spec.feet}
        self.stop()

    # -- actions ---------------------------------------------------------------------
    def switch(self, mode: str, now: int) -> None:
        """``track: off | angles | kd``: start (taking the tracked joints, as any
        action takes the joints it drives) or stop following the performer."""
        if self.mode != OFF and not self.lost:  # (lost: let go already)
            self._let_go()
        self.mode = mode
        self.lost = False
        self.impact_at = None
        self.reaction = self.step = None
        self.prev = None
        if mode == OFF:
            self.busy = False
            return
        self.kinematic = mode == KD
        self.last_sample = now  # a first sample is awaited for lost_after
        self._take(now)
        self.busy = True

    def set_kinematic(self, how: str) -> None:
        """``kinematic: on | off | toggle``: the Cartesian pulls (off: free fall)."""
        self.kinematic = (not self.kinematic) if how == "toggle" else how == "on"
        self.prev = None
        if not self.kinematic:
            self.impact_at = self.reaction = self.step = None

    def sampled(self, now: int) -> None:
        """A channels frame arrived (the runtime's fast path calls this)."""
        self.last_sample = now
        if self.lost:
            self.lost = False
            self._take(now)

    def impact(self, now: int) -> None:
        """A push or a drag has struck the figure: react at the next control step."""
        if self.mode == KD and self.kinematic and self.spec.reaction is not None \
                and not self.lost:
            self.impact_at = now

    @property
    def status(self) -> str:
        """For the HUD: what tracking does now."""
        if self.mode == OFF:
            return ""
        if self.lost:
            return f"tracking {self.mode}: LOST (no sample for {self.spec.lost_after:g} s)"
        pulls = "" if self.mode == ANGLES else (" with pulls" if self.kinematic else
                                                " (pulls off: free fall)")
        if self.reaction is not None and self.mode == KD:
            pulls += f", reacting to a {self.reaction[0]} push"
        return f"tracking {self.mode}{pulls}"

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
        t = (step - start) * self.dt
        if t < spec.hold:
            return spec.weight
        t -= spec.hold
        if t >= spec.recover:
            self.reaction = self.step = None
            return 1.0
        return spec.weight + (1.0 - spec.weight) * t / spec.recover

    # -- the work ----------------------------------------------------------------------
    def _take(self, now: int) -> None:
        mine = [j for j in self.joints if self.joints[j] in self.channels] or list(self.joints)
        self.owners_table.take(mine)
        self.owners_table.claim(mine, TRACK)
        if self.mode == KD:
            self.scale_gains(mine)
        root = self.spec.root
        self.x0 = None
        if root is not None:
            hinge = self._hinge_world()
            x = self.channels.get(root.x)
            self.x0 = hinge[0] - (x if x is not None else 0.0)
        self._write_targets()

    def scale_gains(self, joints) -> None:
        """KD control's inertia-scaled gains on ``joints`` (remembered, to give back)."""
        preset, servos = self.spec.preset, self.character.servos
        for joint in joints:
            inertia = self.inertia[joint]
            k, d = preset.kq * inertia, preset.dq * inertia
            servos[joint].stiffness, servos[joint].damping = k, d
            self.scaled[joint] = (k, d)

    def _give_back(self, joints) -> None:
        """The interface's gains back on ``joints`` that still have KD's (a key that
        took one and set its own gains keeps those)."""
        servos = self.character.servos
        for joint in joints:
            k, d = self.scaled.pop(joint)
            servo = servos[joint]
            if servo.stiffness == k and servo.damping == d:
                self.restore_gains([joint])

    def _let_go(self) -> None:
        self.owners_table.drop(TRACK)
        self._give_back(list(self.scaled))

    def _hinge_world(self) -> tuple[float, float]:
        joint = self.character.spec.joint(self.spec.root.at)
        body = self.character.bodies[joint.parent]
        p = body.local_to_world(joint.anchor)
        return (p[0], p[1])

    def _write_targets(self) -> None:
        table, servos, channels = self.owners_table.table, self.character.servos, self.channels
        for joint, channel in self.joints.items():
            value = channels.get(channel)
            if value is None or table.get(joint) != TRACK:
                continue
            servos[joint].target = self._clamped(joint, math.radians(value))

    def _clamped(self, joint: str, q: float) -> float:
        lim = self.limits.get(joint)
        if lim is None:
            return q
        return lim[0] if q < lim[0] else lim[1] if q > lim[1] else q

    def tick(self, step: int) -> None:
        if step % self.every or self.mode == OFF:
            return
        if not self.lost and step - self.last_sample > self.lost_steps:
            self.lost = True
            self._let_go()
            self.prev = None
            return
        if self.lost:
            return
        table = self.owners_table.table
        taken = [j for j in self.scaled if table.get(j) != TRACK]
        if taken:  # joints later actions took: their own gains again
            self._give_back(taken)
        if not self.owners_table.holds_any(TRACK):  # every joint taken by later actions
            self.impact_at = None
            return
        self._write_targets()
        if self.mode == KD and self.kinematic and self.spec.root is not None:
            self._pull(step)
        else:
            self.impact_at = None

    def _pull(self, step: int) -> None:
        """Velocity changes that pull each link's centre of mass toward the performed
        pose's (implicit PD over one control period), weaker while reacting to a push.
        The figure is read in one call (``body_state``) and each link's centre and the
        performed pose are worked out with Chipmunk's and ``link_poses``' arithmetic, so
        the pulls are the ones a link-by-link reading gives, to the bit."""
        spec, ch, c = self.spec, self.channels, self.character
        root = spec.root
        x, y, a = ch.get(root.x), ch.get(root.y), ch.get(root.angle)
        if x is None or y is None or a is None:
            return
        if self.x0 is None:
            self.x0 = self._hinge_world()[0] - x
        angle = math.radians(a)
        hinge = c.spec.joint(root.at).anchor
        cos, sin = math.cos(angle), math.sin(angle)
        hx, hy = self.x0 + x, y
        origin = (hx - (cos * hinge[0] - sin * hinge[1]), hy - (sin * hinge[0] + cos * hinge[1]))
        clamped = self._clamped
        radians = math.radians
        q = {j: clamped(j, radians(ch[n])) for j, n in self.joints.items() if n in ch}
        poses = self._performed(origin, angle, cos, sin, q)
        lift = self._lift(poses, hx, ch.get(root.clearance, 0.0))
        T = self.period
        preset, scale = spec.preset, self.scale
        prev = self.prev
        links = self._links()
        targets = {}
        for name, _, _, _, gx, gy in links:
            ox, oy, _, cl, sl = poses[name]
            targets[name] = (ox + cl * gx - sl * gy, oy + sl * gx + cl * gy + lift)
        # The performed velocities, from the last two samples (a stream's frames come
        # at their own rate, not the control rate's): held between samples.
        sample = self.last_sample
        for name in self.soles:  # the feet's performed angles ride along
            targets[name] = targets[name] + (poses[name][2],)
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
            mass = c.mass
            com = (sum(c.bodies[n].mass * p[0] for n, p in targets.items()) / mass,
                   sum(c.bodies[n].mass * p[1] for n, p in targets.items()) / mass)
            vx = sum(c.bodies[n].mass * v[0] for n, v in vel.items()) / mass
            self._react(step, com, vx)
        weight = self._weight(step)
        stepping = self.step[0] if self.step is not None else None
        table, joint_of, soles = self.owners_table.table, self.joint_of, self.soles
        state = self._reader.read(c.bodies[c.root].space)  # every body, one call
        kp, dp, sqrt = preset.kp, preset.dp, math.sqrt
        set_velocity, set_spin = _cp.cpBodySetVelocity, _cp.cpBodySetAngularVelocity
        for name, cb, i, m, gx, gy in links:
            joint = joint_of.get(name)
            if joint is not None and table.get(joint) != TRACK:
                continue  # a link the performer does not drive (a key took its joint)
            target = targets[name]
            px, py = target[0], target[1]
            s = scale.get(name, 1.0)
            w = weight
            if name == stepping:  # the protective step, then back to the performance
                px, py = self._stepped(step, weight, px, py)
                w = 1.0
            k, d = kp * s * w, dp * sqrt(s) * w  # same ratio
            if k == 0.0 and d == 0.0:
                continue
            tvx, tvy = vel.get(name, (0.0, 0.0))
            bx, by, ba, vx, vy, spin = state[i:i + 6]
            cb_, sb = math.cos(ba), math.sin(ba)  # its centre: cpBodyLocalToWorld's sums
            wx, wy = cb_ * gx + -sb * gy + bx, sb * gx + cb_ * gy + by
            den = m / T + k * T + d
            set_velocity(cb, ((m * vx / T + k * (px - wx) + d * tvx) / den,
                              (m * vy / T + k * (py - wy) + d * tvy) / den))
            if name in soles:  # a foot is also turned flat as performed (its sole
                # stands on the ground; the ankle's inertia-scaled gain alone is weak)
                inertia = c.bodies[name].moment
                kt, dt_ = k * inertia / m, d * inertia / m  # the same natural frequency
                want = poses[name][2]
                turn = want - ba
                turn -= 2 * math.pi * round(turn / (2 * math.pi))
                set_spin(cb, (inertia * spin / T + kt * turn + dt_ * self.spin.get(name, 0.0))
                         / (inertia / T + kt * T + dt_))

    def _links(self) -> list[tuple]:
        """Per pulled link: (name, C body, where its values start in a bulk reading,
        mass, centre of gravity x, y), for the bodies now (a restore re-binds them)."""
        bodies = self.character.bodies
        cached = self.__dict__.get("_link_rows")
        space = bodies[self.character.root].space
        if cached is None or cached[0] is not bodies or cached[1] is not space:
            reader = self._reader
            rows = []
            for name in self.pulled:
                body = bodies[name]
                gx, gy = body.center_of_gravity
                rows.append((name, body._body, reader.offset(space, body), body.mass, gx, gy))
            cached = self._link_rows = (bodies, space, rows)
        return cached[2]

    def _performed(self, origin, angle: float, cos: float, sin: float, q: dict) -> dict:
        """``link_poses`` (the performed pose's links), each with the cosine and sine of
        its turn, worked out once for its children, its centre and its sole."""
        poses = {self.character.spec.root: (origin[0], origin[1], angle, cos, sin)}
        mcos, msin = math.cos, math.sin
        for name, parent, child, ax, ay in self._chain:
            px, py, pa, c, s = poses[parent]
            wx, wy = px + c * ax - s * ay, py + s * ax + c * ay  # the hinge in the world
            a = pa + q.get(name, 0.0)
            c, s = mcos(a), msin(a)
            poses[child] = (wx - (c * ax - s * ay), wy - (s * ax + c * ay), a, c, s)
        return poses

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

    def _lift(self, poses, x: float, clearance: float) -> float:
        """How far up (or down) the performed pose must go for its lowest foot to stand
        on the ground - or to be ``clearance`` above it, in a performer's jump: the
        performer's proportions differ from the figure's, and a foot held in the air by
        the pulls would leave the figure hanging on them."""
        if not self.soles or self.ground_at is None:
            return 0.0
        ground = self.ground_at(x)
        if ground is None:
            return 0.0
        lowest = math.inf
        for link, points in self.soles.items():
            _, oy, _, cl, sl = poses[link]
            for px, py, r in points:
                y = oy + sl * px + cl * py - r
                if y < lowest:
                    lowest = y
        return ground + (clearance if clearance > 0.0 else -PRESS) - lowest

    def next_wakeup(self, earliest: int) -> int | None:
        if self.mode == OFF:
            return None
        return -(-earliest // self.every) * self.every

    def owners(self) -> set[Owner]:
        return {TRACK} if self.mode != OFF else set()

    def get_state(self):
        prev = None if self.prev is None else [
            {n: list(p) for n, p in self.prev.items()}, self.prev_step,
            {n: list(v) for n, v in self.vel.items()}, dict(self.spin)]
        reaction = None if self.reaction is None else list(self.reaction)
        return [self.mode, self.kinematic, self.lost, self.last_sample, self.x0, prev,
                self.impact_at, reaction, {j: list(g) for j, g in self.scaled.items()},
                None if self.step is None else list(self.step)]

    def set_state(self, state) -> None:
        (self.mode, self.kinematic, self.lost, self.last_sample, self.x0, prev,
         self.impact_at, reaction, scaled, step) = state
        self.step = None if step is None else list(step)
        self.scaled = {j: tuple(g) for j, g in scaled.items()}
        self.reaction = None if reaction is None else tuple(reaction)
        self.prev, self.prev_step, self.vel, self.spin = None, -1, {}, {}
        if prev is not None:
            self.prev = {n: tuple(p) for n, p in prev[0].items()}
            self.prev_step = prev[1]
            self.vel = {n: tuple(v) for n, v in prev[2].items()}
            self.spin = dict(prev[3])
        self.busy = self.mode != OFF

    def adopt(self, old: Tracker, same, now: int) -> set[Owner]:
        if old.mode != OFF and self.spec is not None and same("tracking", ""):
            self.set_state(old.get_state())
            return {TRACK}
        if old.scaled:  # tracking ends with the old file: the joints' own gains back
            self.restore_gains(list(old.scaled))
        return set()

    def stop(self) -> None:
        self.mode = OFF
        self.kinematic = False
        self.lost = False
        self.last_sample = 0
        self.x0 = None
        self.prev = None  # the performed link positions at the last sample
        self.prev_step = -1  # ... the step that sample came at
        self.vel: dict = {}  # ... and their velocities from the two last samples
        self.spin: dict = {}  # ... and the feet's turning rates
        self.scaled: dict[str, tuple[float, float]] = {}  # joint -> KD gains it was given
        self.impact_at: int | None = None  # a push to judge at the next control step
        self.reaction: tuple[str, int] | None = None  # (case, step it began)
        self.step: list | None = None  # a large push's protective step (_protective_step)
        self.busy = False


def _lowest_points(character, link: str) -> list[tuple[float, float, float]]:
    """A link's shape points (model frame) with the radius to take off: polygon
    vertices, segment ends, circle centres."""
    import pymunk

    out = []
    for shape in character.shapes[link]:
        if isinstance(shape, pymunk.Poly):
            out += [(v.x, v.y, shape.radius) for v in shape.get_vertices()]
        elif isinstance(shape, pymunk.Segment):
            out += [(shape.a.x, shape.a.y, shape.radius), (shape.b.x, shape.b.y, shape.radius)]
        elif isinstance(shape, pymunk.Circle):
            out.append((shape.offset.x, shape.offset.y, shape.radius))
    return out


def _inertia_beyond(character, joint: str) -> float:
    """kg*m^2: the links a joint moves, about its hinge, with the figure straight (the
    tracker's gain scale; ZH02 and Nguyen use a constant)."""
    spec = character.spec
    ax, ay = spec.joint(joint).anchor
    total = 0.0
    for link in beyond(spec, joint):
        body = character.bodies[link]
        gx, gy = body.center_of_gravity  # model frame: the link's frame at rest
        total += body.moment + body.mass * ((gx - ax) ** 2 + (gy - ay) ** 2)
    return total
