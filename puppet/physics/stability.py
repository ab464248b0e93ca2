"""Will a character stand? Its start pose held by its own servos on a flat floor.

``puppet check CHARACTER`` runs this so that a designer learns in seconds what a body
does with its targets held, instead of by playing it: whether it stands for 5 s of
simulated time, whether it stands again after a small nudge, which joints oscillate
(a sustained swing with nothing driving it), which joints sag from their targets or
hit their torque limit, and which joints the engine all but locks.

The lock is pymunk's (Chipmunk's) damped rotary spring, which puppet's servos are:
the solver takes the damping implicitly, multiplying the joint's relative speed by
``exp(-lam)`` each step with ``lam = damping * dt * (1/I_parent + 1/I_child)``. Against a
light link (a foot, a paw) ``lam`` is large, and the joint then follows a new target
about ``(e^lam - 1) / lam`` times slower than damping / stiffness says (the biped's
ankle: 10^4 times). Measured per joint from the bodies' own moments, no run needed.

The static part reads the start pose, once it is on the floor: for each joint (joints that
share a hinge point in the model frame, a near and a far leg, counted together), the mass
on its far side from the ground, how high its centre of mass is over the hinge
(``m g h``: the stiffness an inverted pendulum needs just to stay up) and how far out
(the torque the joint must give to hold it still).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from puppet.data.characters import CharacterSpec
from puppet.data.scenes import GroundSpec, SceneSpec
from puppet.physics.kinematics import beyond
from puppet.physics.simulation import Simulation, step_of

SECONDS = 5.0  # simulated seconds the start pose is held
TAIL = 2.0  # s at the end over which oscillation is measured
NUDGE_AT = 1.0  # s: when the nudged run is nudged
NUDGE = 0.05  # the nudge's speed, as a fraction of sqrt(g * the centre of mass's height)
FALL_TILT = 45.0  # deg the root may turn from its start angle before the body has fallen
FALL_DROP = 0.5  # the centre of mass below this fraction of its start height: fallen
SWING_DEG = 0.5  # deg: a sustained swing at least this large is an oscillation
SAG_DEG = 3.0  # deg from its target at the end: the joint sags
TIP_DEG = 10.0  # deg the root turns while held, standing: it settles into another pose
LOCK_LAM = 6.5  # lam above this: damping acts over 100x its number (the joint locks)
TRACK_LAM = 3.0  # lam up to this still tracks (the damping the report suggests)
TOPPLE_MARGIN = 1.5  # stiffness below this many times m g h is reported as too soft
LOADS_AT = 0.05  # s: when the loads are measured (the start pose, on the floor)

FLOOR = SceneSpec(name="a flat floor", description="the stability check's floor",
                  ground=[GroundSpec(points=[(-100.0, 0.0), (100.0, 0.0)])])


@dataclass
class Run:
    """What one held-pose run did."""
    fell_at: float | None = None  # s
    why: str = ""  # how it fell
    blew_up: bool = False
    tilt: float = 0.0  # deg the root turned from its start angle, at the end
    com_start: tuple[float, float] = (0.0, 0.0)
    com_end: tuple[float, float] = (0.0, 0.0)
    settled_at: float | None = None  # s: the last time it moved faster than 1 cm/s


@dataclass
class Joint:
    """One actuated joint's findings (degrees, seconds, N*m)."""
    name: str
    swing: float = 0.0  # deg: half the peak-to-peak of the last TAIL s
    hz: float = 0.0  # its frequency
    sag: float = 0.0  # deg from the target at the end (signed)
    capped: float = 0.0  # fraction of the run spent at the torque limit
    lam: float = 0.0  # the solver's damping exponent per step
    light: str = ""  # the lighter of its two links
    light_moment: float = 0.0  # kg*m^2
    track_damping: float = 0.0  # the damping at which lam = TRACK_LAM
    follow: float = 0.0  # s: about how long it takes to follow a new target


@dataclass
class Load:
    """What a joint (or a pair sharing its hinge) carries, away from the ground."""
    joints: list[str]
    mass: float  # kg carried
    topple: float  # m g h, N*m/rad (0 when the load hangs below the hinge)
    stiffness: float  # the joints' stiffness together
    torque: float  # N*m the load's weight pulls with
    max_torque: float  # the joints' together


@dataclass
class Stability:
    quiet: Run
    nudged: Run
    nudge: float  # m/s given to every link at NUDGE_AT
    joints: list[Joint] = field(default_factory=list)
    loads: list[Load] = field(default_factory=list)
    touching: list[str] = field(default_factory=list)  # links on the floor, at the end
    dt: float = 0.0
    touching_start: list[str] = field(default_factory=list)  # ... at LOADS_AT
    # (the centre of mass's x, (the support's left x, right x) or None) at LOADS_AT
    balance: tuple | None = None
    mass: float = 0.0  # kg, the whole body

    @property
    def off_support(self) -> float:
        """m the start pose's centre of mass is ahead (+) or behind (-) its support (0:
        over it)."""
        if self.balance is None or self.balance[1] is None:
            return 0.0
        x, (left, right) = self.balance[0], self.balance[1]
        return x - right if x > right else x - left if x < left else 0.0

    @property
    def stands(self) -> bool:
        return self.quiet.fell_at is None

    @property
    def oscillating(self) -> list[Joint]:
        return [j for j in self.joints if j.swing >= SWING_DEG and j.hz >= 0.5]

    @property
    def locked(self) -> list[Joint]:
        return [j for j in self.joints if j.lam > LOCK_LAM]


def _hold(spec: CharacterSpec, nudge: float | None, probe=None) -> tuple[Run, Simulation]:
    """The start pose held for SECONDS on FLOOR; ``nudge`` (m/s, forward) given to every
    link at NUDGE_AT. ``probe(sim, t)`` is called after every step."""
    sim = Simulation(spec, FLOOR, step_of(spec))  # on the step its sessions take
    c = sim.character
    run = Run(com_start=c.com())
    a0 = c.root_angle()
    floor = 0.0
    height = max(1e-6, run.com_start[1] - floor)
    steps = round(SECONDS / sim.dt)
    nudge_step = round(NUDGE_AT / sim.dt)
    for i in range(1, steps + 1):
        sim.step(1)
        t = i * sim.dt
        if nudge is not None and i == nudge_step:
            for body in c.bodies.values():
                body.velocity = (body.velocity.x + nudge, body.velocity.y)
        if i % 24 == 0 and sim.blown_up():
            run.blew_up, run.fell_at = True, t
            run.why = "the simulation blew up (a joint too stiff for the time step)"
            break
        if probe is not None:
            probe(sim, t)
        if run.fell_at is None:
            tilt = math.degrees(c.root_angle() - a0)
            com = c.com()
            if abs(tilt) > FALL_TILT:
                run.fell_at, run.why = t, f"the root link turned {abs(tilt):.0f} deg"
            elif com[1] - floor < FALL_DROP * height:
                run.fell_at, run.why = t, (f"the centre of mass sank from {height:.2f} to "
                                           f"{com[1] - floor:.2f} m")
        if i % 24 == 0 and math.hypot(*c.com_velocity()) > 0.01:
            run.settled_at = t
    run.tilt = math.degrees(c.root_angle() - a0)
    run.com_end = c.com()
    return run, sim


def _oscillation(samples: list[float], seconds: float) -> tuple[float, float]:
    """(half the peak-to-peak, frequency in Hz) of a joint's angle samples: a swing is
    counted each time the angle crosses its mean by more than a third of the swing."""
    if not samples:
        return 0.0, 0.0
    mean = sum(samples) / len(samples)
    swing = (max(samples) - min(samples)) / 2
    band = max(0.05, swing / 3)
    side, crossings = 0, 0
    for v in samples:
        s = 1 if v - mean > band else -1 if v - mean < -band else 0
        if s and s != side:
            crossings += 1 if side else 0
            side = s
    return swing, crossings / 2 / seconds


def _locks(spec: CharacterSpec, sim: Simulation) -> dict[str, tuple]:
    """joint -> (lam, lighter link, its moment, damping at TRACK_LAM, seconds to follow)."""
    out = {}
    for joint in spec.actuated:
        a, b = sim.character.bodies[joint.parent], sim.character.bodies[joint.child]
        inverse = 1.0 / a.moment + 1.0 / b.moment
        k, d = joint.pd.stiffness, joint.pd.damping
        lam = d * sim.dt * inverse
        slower = math.expm1(lam) / lam if lam > 1e-9 else 1.0
        light, moment = ((joint.parent, a.moment) if a.moment < b.moment
                         else (joint.child, b.moment))
        follow = (d / k) * slower if k > 0 else math.inf
        out[joint.name] = (lam, light, moment, TRACK_LAM / (sim.dt * inverse), follow)
    return out


def _loads(spec: CharacterSpec, sim: Simulation, touching: list[str]) -> list[Load]:
    """Each hinge's load away from the ground, in the pose the run ended in."""
    c = sim.character
    g = abs(sim.space.gravity[1])
    groups: dict[tuple, list] = {}  # a near and a far leg share their hinge points
    for joint in spec.actuated:
        groups.setdefault(tuple(round(v, 4) for v in joint.anchor), []).append(joint)
    out = []
    for joints in groups.values():
        parent, anchor = joints[0].parent, joints[0].anchor
        moved = set(beyond(spec, joints[0].name))
        for j in joints[1:]:
            moved |= set(beyond(spec, j.name))
        grounded_moved = any(link in moved for link in touching)
        grounded_rest = any(link not in moved for link in touching)
        if grounded_moved == grounded_rest:  # both sides or neither on the floor
            continue
        carried = [n for n in c.link_order if (n in moved) != grounded_moved]
        mass = sum(c.bodies[n].mass for n in carried)
        if mass <= 0:
            continue
        cx = sum(c.bodies[n].mass * c.bodies[n].local_to_world(
            c.bodies[n].center_of_gravity).x for n in carried) / mass
        cy = sum(c.bodies[n].mass * c.bodies[n].local_to_world(
            c.bodies[n].center_of_gravity).y for n in carried) / mass
        hinge = c.bodies[parent].local_to_world(anchor)
        out.append(Load(joints=[j.name for j in joints], mass=mass,
                        topple=max(0.0, mass * g * (cy - hinge.y)),
                        stiffness=sum(j.pd.stiffness for j in joints),
                        torque=mass * g * abs(cx - hinge.x),
                        max_torque=sum(j.pd.max_torque for j in joints)))
    return out


def stability(spec: CharacterSpec) -> Stability:
    """Hold the start pose SECONDS (quiet), and again with a nudge; measure."""
    tail_from = SECONDS - TAIL
    angles: dict[str, list[float]] = {j.name: [] for j in spec.actuated}
    capped = dict.fromkeys(angles, 0)

    start: dict[str, list] = {}  # the loads in the start pose, once it touches down

    def probe(sim: Simulation, t: float) -> None:
        if not start and t >= LOADS_AT:
            c = sim.character
            start["touching"] = [n for n in c.link_order if c.in_contact(n)]
            start["loads"] = _loads(spec, sim, start["touching"])
            start["balance"] = (c.com()[0], c.support_extent())
        for name, servo in sim.character.servos.items():
            if t > tail_from:
                angles[name].append(math.degrees(servo.angle))
            if abs(servo.torque(sim.dt)) >= 0.99 * servo.max_torque:
                capped[name] += 1

    quiet, sim = _hold(spec, None, probe)
    height = max(1e-6, quiet.com_start[1])
    nudge = NUDGE * math.sqrt(abs(FLOOR.gravity[1]) * height)
    nudged, _ = _hold(spec, nudge)
    touching = [n for n in sim.character.link_order if sim.character.in_contact(n)]
    steps = max(1, sim.steps)
    locks = _locks(spec, sim)
    joints = []
    for joint in spec.actuated:
        servo = sim.character.servos[joint.name]
        swing, hz = _oscillation(angles[joint.name], TAIL)
        lam, light, moment, track, follow = locks[joint.name]
        joints.append(Joint(joint.name, swing, hz, math.degrees(servo.angle - servo.target),
                            capped[joint.name] / steps, lam, light, moment, track, follow))
    return Stability(quiet, nudged, nudge, joints, start.get("loads", []), touching, sim.dt,
                     start.get("touching", []), start.get("balance"), sim.character.mass)
