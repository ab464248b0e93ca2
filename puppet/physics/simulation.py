"""The simulation: one character in one scene, stepped at a fixed time step.

Fixed step, no wall clock: the same inputs at the same step indices give the same
bits. pymunk does not keep the solver's warm-start state across a copy or a pickle
(constraints' accumulated impulses, the spatial index's pair cache), so a restored
copy drifts from the original; two restores of one snapshot agree exactly. Callers
that need "restored == never restored" (checkpoints) re-seat the live run on a
restored copy at the moment they snapshot: see ``checkpoint()``. Sessions do so at
step 0, so every run's bits depend on exactly how ``restore`` builds the space. A
checkpoint re-seats the run in place (``puppet.physics.reseat``: the space and the
objects are kept, put in the state a fresh space built from the snapshot has); a
restore does too when the live objects still match the snapshot's, else it builds a
fresh space. Either way callers re-read the objects (``character.bodies``, grasps...),
and ``seats`` counts the re-seats.

The snapshot format itself is ``puppet.physics.snapshot``. The Simulation owns every
constraint the interface adds to the world (grasps, the Ctrl+drag spring), so that
snapshots, rewinds and replays cover them exactly.
"""

from __future__ import annotations

import hashlib
import math
import pickle
import struct

import pymunk
from pymunk._chipmunk_cffi import lib as _cp

from puppet.data.characters import CharacterSpec
from puppet.data.scenes import SceneSpec
from puppet.physics import kernel as _kernel
from puppet.physics import props as prop_bodies
from puppet.physics import snapshot
from puppet.physics.character import Character
from puppet.physics.props import Prop
from puppet.physics.scene import build_ground

DEFAULT_DT = 1.0 / 480.0  # s; small enough for stiff hopping servos on light links
SOLVER_ITERATIONS = 20
COLLISION_SLOP = 0.0005  # m; pymunk's default (0.1) assumes pixel units
DRAG_STIFFNESS_PER_KG = 200.0  # N/m per kg of character, for Ctrl+drag
MAX_SPEED = 200.0  # m/s; beyond this the state has blown up


def queued(space: pymunk.Space) -> bool:
    """Whether pymunk's ``Space.step`` has Python work before its C step (its queues, a
    post-step callback, threads): then ``step_space`` takes pymunk's own step."""
    return bool(space._bodies_to_check or space._add_later or space._remove_later
                or space._post_step_callbacks or space.threaded)


def step_space(space: pymunk.Space, dt: float, n: int) -> None:
    """``n`` times ``space.step(dt)``: the same C step, so the same bits, without the
    Python around it in pymunk's ``Space.step`` (its queues, lock and mass check: 1-2 us a
    step, about a tenth of the figure's whole step). That bookkeeping has work only when
    a body was just added or a collision or post-step callback changed the space inside a
    step; puppet has no such callbacks, and a space with anything queued takes pymunk's
    own step until the queues are empty."""
    step = _cp.cpSpaceStep
    while n > 0 and queued(space):
        space.step(dt)
        n -= 1
    if space._removed_shapes:  # what Space.step lets go of after its C step
        space._removed_shapes.clear()
    ptr = space._space
    for _ in range(n):
        step(ptr, dt)


def step_of(character: CharacterSpec) -> float:
    """The simulation step a new session of ``character`` runs on, s: its own
    (``solver: {step: ...}``) or DEFAULT_DT. A replay runs on its log's ('dt' in the
    header), whatever the character says today."""
    return character.solver.dt or DEFAULT_DT


class Simulation:
    def __init__(self, character: CharacterSpec, scene: SceneSpec, dt: float = DEFAULT_DT):
        self.character_spec = character
        self.scene_spec = scene
        self.dt = dt
        self.steps = 0
        self.seats = 0  # checkpoints and restores so far (each re-seats the run)
        self.space = pymunk.Space()
        self.space.gravity = scene.gravity
        solver = character.solver  # a character may need more passes or less slop
        self.space.iterations = solver.iterations or SOLVER_ITERATIONS
        self.space.collision_slop = solver.collision_slop or COLLISION_SLOP
        self.ground = build_ground(scene, self.space)
        self.props: dict[str, Prop] = prop_bodies.build_props(scene, self.space)
        # grasps held now: name (a chain) -> (pivot joint, prop name or None for the world)
        self.grasps: dict[str, tuple[pymunk.PivotJoint, str | None]] = {}
        # rigid grasps' angle holds: name -> the gear joint next to the grasp's pivot
        self.rigid: dict[str, pymunk.GearJoint] = {}
        self.character = Character(character)
        self.character.add_to(self.space)
        self.character.set_step(dt)  # the servos' damping, the same at any step
        self._place_at_start()
        self.drag_body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.drag_spring: pymunk.DampedSpring | None = None
        self.space.add(self.drag_body)

    def _place_at_start(self) -> None:
        c, start = self.character, self.scene_spec.start
        angle = math.radians(self.character_spec.start.angle)
        # the root turned first: place() puts the origin, then turns the root, and pymunk
        # turns a body about its centre of gravity (a start_angle would move it off)
        c.bodies[c.spec.root].angle = angle
        c.place(start.x, 0.0, angle, c.start_joint_angles())
        ground = self.scene_spec.ground_height(start.x)
        floor = start.y if ground is None else max(ground, start.y)
        lift = floor + self.character_spec.start.lift + 0.002 - c.lowest_point()
        c.place(start.x, lift, angle, c.start_joint_angles())

    # -- time --------------------------------------------------------------------
    @property
    def time(self) -> float:
        return self.steps * self.dt

    def step(self, n: int = 1) -> None:
        # Session.advance steps the space itself, the same way (its hot loop).
        step_space(self.space, self.dt, n)
        self.steps += n

    # -- Ctrl+drag: a spring from a point on a body to a target (the viewer convention)
    def start_drag(self, link: str, local_point: tuple[float, float],
                   target: tuple[float, float]) -> None:
        self.end_drag()
        body = self.character.bodies[link]
        k = DRAG_STIFFNESS_PER_KG * self.character.mass
        damping = 2.0 * math.sqrt(k * self.character.mass) * 0.3
        self.drag_body.position = target
        self.drag_spring = pymunk.DampedSpring(self.drag_body, body, (0, 0), local_point,
                                               0.0, k, damping)
        self.space.add(self.drag_spring)

    def move_drag(self, target: tuple[float, float]) -> None:
        self.drag_body.position = target

    def end_drag(self) -> None:
        if self.drag_spring is not None:
            self.space.remove(self.drag_spring)
            self.drag_spring = None

    def ground_surface(self, x: float) -> float | None:
        """The height of the ground's top under ``x`` (its line plus half its
        thickness), None off its ends."""
        spec = self.scene_spec
        got = self.__dict__.get("_ground_spans")
        if got is None or got[0] is not spec:  # (KD tracking asks at every control step)
            got = self._ground_spans = (spec, [
                (min(x0, x1), max(x0, x1), x0, y0, x1, y1, ground.thickness / 2)
                for ground in spec.ground
                for (x0, y0), (x1, y1) in zip(ground.points, ground.points[1:])
                if x1 != x0])
        best = None
        for lo, hi, x0, y0, x1, y1, half in got[1]:
            if lo <= x <= hi:
                y = y0 + (y1 - y0) * (x - x0) / (x1 - x0) + half
                best = y if best is None else max(best, y)
        return best

    def push(self, link: str, impulse: tuple[float, float], point=None) -> None:
        """A shove: ``impulse`` (N*s, world) at ``point`` of ``link`` (model frame, m;
        None: its centre of mass). Unknown links are ignored (a log from elsewhere)."""
        body = self.character.bodies.get(link)
        if body is None:
            return
        # a body's local frame is the model frame placed at the body (character.py)
        local = body.center_of_gravity if point is None else tuple(point)
        body.apply_impulse_at_local_point(impulse, local)

    # -- grasps: a pivot pinning a point of a link to the world or to a prop ----------
    def attach(self, name: str, link: str, local_point: tuple[float, float],
               world_point: tuple[float, float], prop: str | None = None,
               rigid: bool = False, max_torque: float | None = None) -> None:
        """Pin ``local_point`` of ``link`` to ``world_point`` on ``prop`` (None: the
        static world), as grasp ``name`` (replacing a grasp of that name). A link does
        not collide with the prop it holds. ``rigid``: also hold the link's angle to the
        prop (the world) as it is now, with at most ``max_torque`` N*m (None: no limit) -
        a gear joint of ratio 1 next to the pivot, let go with it."""
        self.detach(name)
        body = self.character.bodies[link]
        if prop is None:
            other = self.space.static_body
            joint = pymunk.PivotJoint(body, other, local_point, world_point)
        else:
            other = self.props[prop].body
            joint = pymunk.PivotJoint(body, other, local_point, other.world_to_local(world_point))
            joint.collide_bodies = False
        self.space.add(joint)
        self.grasps[name] = (joint, prop)
        if rigid:
            # Chipmunk's gear joint holds b.angle * ratio - a.angle at its phase
            gear = pymunk.GearJoint(body, other, other.angle - body.angle, 1.0)
            gear.collide_bodies = joint.collide_bodies
            if max_torque is not None:
                gear.max_force = max_torque
            self.space.add(gear)
            self.rigid[name] = gear

    def detach(self, name: str) -> None:
        held = self.grasps.pop(name, None)
        if held is not None:
            self.space.remove(held[0])
        gear = self.rigid.pop(name, None)
        if gear is not None:
            self.space.remove(gear)

    def grasp_point(self, name: str) -> tuple[float, float] | None:
        """World point where grasp ``name`` holds (None if it does not)."""
        held = self.grasps.get(name)
        if held is None:
            return None
        joint = held[0]
        p = joint.b.local_to_world(joint.anchor_b)
        return (p[0], p[1])

    # -- physical parameters ---------------------------------------------------------
    @property
    def gravity(self) -> tuple[float, float]:
        return tuple(self.space.gravity)

    @gravity.setter
    def gravity(self, value: tuple[float, float]) -> None:
        self.space.gravity = value

    # -- state -------------------------------------------------------------------
    def snapshot(self) -> bytes:
        """The whole physical state as self-contained bytes (restore with ``restore``)."""
        return pickle.dumps(self._state(), protocol=pickle.HIGHEST_PROTOCOL)

    def restore(self, data: bytes | Kept) -> None:
        """Back to a ``snapshot`` (or a ``keep``): re-seated in place, or on a fresh
        space (the objects callers held are then replaced)."""
        self._rebuild(data.state() if type(data) is Kept else pickle.loads(data))

    def checkpoint(self) -> bytes:
        """Snapshot, and continue from a restored copy so that any later restore of
        this snapshot replays bit-identically to the run that never restored."""
        state = self._state()
        data = pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL)
        self._rebuild(state)  # plain values: the same as ``pickle.loads(data)``
        return data

    def keep(self) -> Kept:
        """``checkpoint``, its state kept as captured (``Kept``: pickled only when the
        history's memory asks for it), the same bits on restore."""
        state = self._state()
        self._rebuild(state)
        return Kept(state)

    def _state(self) -> tuple:
        named = {"character": self.character.state_objects(), "ground": self.ground,
                 "drag": [self.drag_body] + ([] if self.drag_spring is None
                                             else [self.drag_spring])}
        if self.props:
            named["props"] = prop_bodies.objects(self.props)
        if self.grasps:
            named["grasps"] = [joint for joint, _ in self.grasps.values()]
        for name, gear in self.rigid.items():  # only rigid grasps add names
            named["rigid " + name] = [gear]
        holders = [(name, prop) for name, (_, prop) in self.grasps.items()]
        return snapshot.capture(self.space, named), holders, self.steps

    def _rebuild(self, state: tuple) -> None:
        space_state, holders, steps = state
        self.space, named = snapshot.rebuild(space_state, into=self.space)
        self.seats += 1
        self.character.bind(named["character"])
        self.ground = named["ground"]
        self.drag_body, *spring = named["drag"]
        self.drag_spring = spring[0] if spring else None
        if self.props:
            prop_bodies.bind(self.props, named["props"])
        self.grasps = {name: (joint, prop) for (name, prop), joint
                       in zip(holders, named.get("grasps", ()))}
        self.rigid = {key[6:]: objs[0] for key, objs in named.items()
                      if key.startswith("rigid ")}
        self.steps = steps

    def state_vector(self) -> list[float]:
        """Position, angle, velocity and angular velocity of every body, in link order,
        then of every dynamic prop."""
        out: list[float] = []
        bodies = [self.character.bodies[name] for name in self.character.link_order]
        bodies += [p.body for p in self.props.values() if p.body.body_type == pymunk.Body.DYNAMIC]
        for b in bodies:
            out += (b.position.x, b.position.y, b.angle, b.velocity.x, b.velocity.y,
                    b.angular_velocity)
        return out

    def state_hash(self) -> str:
        vec = self.state_vector()
        return hashlib.sha256(struct.pack(f"<{len(vec)}d", *vec)).hexdigest()[:16]

    def blown_up(self) -> bool:
        """NaN or runaway velocity anywhere (the state can no longer be trusted). It runs
        at every health check (each 0.5 s of a run), so it reads the bodies through
        pymunk's own C calls (what ``velocity``, ``position`` and ``angle`` return), or
        in one call of the kernel (``kernel_health``: the same tests)."""
        kern = _kernel.get()
        if kern is not None:
            bodies = self.character.bodies
            rows = self.__dict__.get("_health_rows")
            if rows is None or rows[0] is not bodies:  # (a re-seat: new bodies)
                rows = self._health_rows = (bodies, kern.ffi.new(
                    "void *[]", [kern.pointer(b._body) for b in bodies.values()]))
            return bool(kern.lib.pk_blown_up(rows[1], len(bodies), MAX_SPEED ** 2,
                                             50 * MAX_SPEED))
        isfinite = math.isfinite
        for b in self.character.bodies.values():
            cb = b._body
            v, p = _cp.cpBodyGetVelocity(cb), _cp.cpBodyGetPosition(cb)
            vx, vy, x, y = v.x, v.y, p.x, p.y
            w = _cp.cpBodyGetAngularVelocity(cb)
            if not (isfinite(vx) and isfinite(vy) and isfinite(w) and isfinite(x)
                    and isfinite(y) and isfinite(_cp.cpBodyGetAngle(cb))):
                return True
            if vx * vx + vy * vy > MAX_SPEED ** 2 or abs(w) > 50 * MAX_SPEED:
                return True
        return False


class Kept:
    """A checkpoint's state as ``Simulation._state`` captured it: plain values that
    nothing mutates (``snapshot.rebuild`` and ``reseat`` only read their input; tests/
    test_kept_state.py checks it), so restoring from them is restoring from their
    pickle (``pickle.loads`` of plain values gives equal values, the same bits) without
    the pickle's cost. ``freeze`` pickles them, at a fifth of the memory, once the
    history keeps enough of them unpickled (``History``)."""

    __slots__ = ("_state", "_data")

    def __init__(self, state: tuple):
        self._state: tuple | None = state
        self._data: bytes | None = None

    def state(self) -> tuple:
        got = self._state
        return pickle.loads(self._data) if got is None else got

    def freeze(self) -> None:
        if self._state is not None:
            self._data = pickle.dumps(self._state, protocol=pickle.HIGHEST_PROTOCOL)
            self._state = None

    @property
    def frozen(self) -> bool:
        return self._state is None

    def __len__(self) -> int:
        """The size of its pickle (what it holds once frozen), bytes."""
        return len(self._data if self._state is None
                   else pickle.dumps(self._state, protocol=pickle.HIGHEST_PROTOCOL))
