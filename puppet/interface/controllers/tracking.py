"""Tracking a performance: mocap channels drive the figure (``tracking:`` section).

``angles``: each tracked joint's target is its channel's angle (clamped to the joint's
limits). ``kd`` (Nguyen et al. 2010): the same targets with inertia-scaled gains, and
Cartesian PD pulls of each link's centre of mass toward where the performed pose -
the root channels placing the root joint's hinge, the joint channels bending the rest
- puts it, scaled by ``scale`` (feet strongest, for balance). Two deliberate changes
from the paper's ``u = kp (p* - p) - dp v``: the damping acts on the velocity relative
to the performed one (a walking target is followed without drag), a link's ``scale``
multiplies kp and its square root dp (the damping ratio stays the paper's; a foot
damped 125x would lag the performance by a fifth of a second), and the pull is
integrated implicitly (backward Euler, as a velocity change each control step), so a
foot's 125x gain stays stable at any control rate.

Everything runs on absolute multiples of the control period and reads only the
channels, the figure's state and its own plain state, so a replay (or a restored
checkpoint) does the same to the bit. A stream with no sample for ``lost_after`` s is
lost: the tracker lets go of its joints (and the figure's gains go back) until samples
come again, when it takes its joints back as a new action would.
"""

from __future__ import annotations

import math

from puppet.data.tracking import TrackingSpec
from puppet.interface.ownership import JointOwners, Owner
from puppet.physics.kinematics import beyond, joint_order, link_poses

TRACK = Owner("track")
OFF, ANGLES, KD = "off", "angles", "kd"


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
        self.restore_gains = restore_gains  # puts the interface's gains back
        self.lost_steps = 0 if spec is None else max(1, round(spec.lost_after / dt))
        cs = character.spec
        self.order = joint_order(cs)
        self.limits = {j.name: (None if j.limits is None else
                                (math.radians(j.limits[0]), math.radians(j.limits[1])))
                       for j in cs.actuated}
        self.joints: dict[str, str] = {}  # tracked joint -> its channel
        if spec is not None:
            names = [j.name for j in cs.actuated] if spec.joints == "all" else spec.joints
            self.joints = {j: spec.channels.get(j, j) for j in names}
        self.inertia = {j: _inertia_beyond(character, j) for j in self.joints}
        self.pulled = [link.name for link in cs.links]
        self.scale = {} if spec is None else dict(spec.scale)
        self.ground_at = ground_at  # x -> the ground's surface height (None: no lift)
        self.soles = {} if spec is None else {f: _lowest_points(character, f) for f in spec.feet}
        self.stop()

    # -- actions ---------------------------------------------------------------------
    def switch(self, mode: str, now: int) -> None:
        """``track: off | angles | kd``: start (taking the tracked joints, as any
        action takes the joints it drives) or stop following the performer."""
        if self.mode != OFF:
            self._let_go()
        self.mode = mode
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

    def sampled(self, now: int) -> None:
        """A channels frame arrived (the runtime's fast path calls this)."""
        self.last_sample = now
        if self.lost:
            self.lost = False
            self._take(now)

    @property
    def status(self) -> str:
        """For the HUD: what tracking does now."""
        if self.mode == OFF:
            return ""
        if self.lost:
            return f"tracking {self.mode}: LOST (no sample for {self.spec.lost_after:g} s)"
        pulls = "" if self.mode == ANGLES else (" with pulls" if self.kinematic else
                                                " (pulls off: free fall)")
        return f"tracking {self.mode}{pulls}"

    # -- the work ----------------------------------------------------------------------
    def _take(self, now: int) -> None:
        mine = [j for j in self.joints if self.joints[j] in self.channels] or list(self.joints)
        self.owners_table.take(mine)
        self.owners_table.claim(mine, TRACK)
        servos = self.character.servos
        if self.mode == KD:
            preset = self.spec.preset
            for joint in mine:
                inertia = self.inertia[joint]
                servos[joint].stiffness = preset.kq * inertia
                servos[joint].damping = preset.dq * inertia
        root = self.spec.root
        self.x0 = None
        if root is not None:
            hinge = self._hinge_world()
            x = self.channels.get(root.x)
            self.x0 = hinge[0] - (x if x is not None else 0.0)
        self._write_targets()

    def _let_go(self) -> None:
        self.owners_table.drop(TRACK)
        if self.mode == KD:
            self.restore_gains(list(self.joints))

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
        if not self.owners_table.holds_any(TRACK):  # every joint taken by later actions
            return
        self._write_targets()
        if self.mode == KD and self.kinematic and self.spec.root is not None:
            self._pull()

    def _pull(self) -> None:
        """Velocity changes that pull each link's centre of mass toward the performed
        pose's (implicit PD over one control period)."""
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
        q = {j: self._clamped(j, math.radians(ch[n])) for j, n in self.joints.items() if n in ch}
        poses = link_poses(c.spec, self.order, origin, angle, q)
        lift = self._lift(poses, hx)
        T = self.period
        preset, scale = spec.preset, self.scale
        prev = self.prev
        targets = {}
        for name in self.pulled:
            body = c.bodies[name]
            ox, oy, la = poses[name]
            gx, gy = body.center_of_gravity
            cl, sl = math.cos(la), math.sin(la)
            px, py = ox + cl * gx - sl * gy, oy + sl * gx + cl * gy + lift
            targets[name] = (px, py)
            s = scale.get(name, 1.0)
            k, d = preset.kp * s, preset.dp * math.sqrt(s)  # the same damping ratio
            if k == 0.0 and d == 0.0:
                continue
            if prev is not None and name in prev:
                tvx, tvy = (px - prev[name][0]) / T, (py - prev[name][1]) / T
            else:
                tvx = tvy = 0.0
            m = body.mass
            p = body.local_to_world(body.center_of_gravity)
            vx, vy = body.velocity
            den = m / T + k * T + d
            body.velocity = ((m * vx / T + k * (px - p[0]) + d * tvx) / den,
                             (m * vy / T + k * (py - p[1]) + d * tvy) / den)
        self.prev = targets

    def _lift(self, poses, x: float) -> float:
        """How far up the performed pose must go for no foot to be under the ground."""
        if not self.soles or self.ground_at is None:
            return 0.0
        ground = self.ground_at(x)
        if ground is None:
            return 0.0
        lowest = math.inf
        for link, points in self.soles.items():
            _, oy, la = poses[link]
            cl, sl = math.cos(la), math.sin(la)
            for px, py, r in points:
                y = oy + sl * px + cl * py - r
                if y < lowest:
                    lowest = y
        return max(0.0, ground - lowest)

    def next_wakeup(self, earliest: int) -> int | None:
        if self.mode == OFF:
            return None
        return -(-earliest // self.every) * self.every

    def owners(self) -> set[Owner]:
        return {TRACK} if self.mode != OFF else set()

    def get_state(self):
        prev = None if self.prev is None else {n: list(p) for n, p in self.prev.items()}
        return [self.mode, self.kinematic, self.lost, self.last_sample, self.x0, prev]

    def set_state(self, state) -> None:
        self.mode, self.kinematic, self.lost, self.last_sample, self.x0, prev = state
        self.prev = None if prev is None else {n: tuple(p) for n, p in prev.items()}
        self.busy = self.mode != OFF

    def adopt(self, old: Tracker, same, now: int) -> set[Owner]:
        if old.mode != OFF and self.spec is not None and same("tracking", ""):
            self.set_state(old.get_state())
            return {TRACK}
        return set()

    def stop(self) -> None:
        self.mode = OFF
        self.kinematic = False
        self.lost = False
        self.last_sample = 0
        self.x0 = None
        self.prev = None
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
