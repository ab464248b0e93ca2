"""The simulation: one character in one scene, stepped at a fixed time step.

Fixed step, no wall clock: the same inputs at the same step indices give the same
bits. ``snapshot()``/``restore()`` pickle the whole space; pymunk does not keep the
solver's warm-start (cached contact impulse) state across a pickle, so a restored
copy would drift from the original. Callers that need "restored == never restored"
(checkpoints) re-seat the live run on a restored copy at the moment they snapshot:
see ``checkpoint()``.
"""

from __future__ import annotations

import hashlib
import math
import pickle
import struct

import pymunk

from puppet.data.characters import CharacterSpec
from puppet.data.scenes import SceneSpec
from puppet.physics.character import Character
from puppet.physics.scene import build_ground

DEFAULT_DT = 1.0 / 480.0  # s; small enough for stiff hopping servos on light links
SOLVER_ITERATIONS = 20
COLLISION_SLOP = 0.0005  # m; pymunk's default (0.1) assumes pixel units
DRAG_STIFFNESS_PER_KG = 200.0  # N/m per kg of character, for Ctrl+drag
MAX_SPEED = 200.0  # m/s; beyond this the state has blown up


class Simulation:
    def __init__(self, character: CharacterSpec, scene: SceneSpec, dt: float = DEFAULT_DT):
        self.character_spec = character
        self.scene_spec = scene
        self.dt = dt
        self.steps = 0
        self.space = pymunk.Space()
        self.space.gravity = scene.gravity
        self.space.iterations = SOLVER_ITERATIONS
        self.space.collision_slop = COLLISION_SLOP
        self.ground = build_ground(scene, self.space)
        self.character = Character(character)
        self.character.add_to(self.space)
        self._place_at_start()
        self.drag_body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.drag_spring: pymunk.DampedSpring | None = None
        self.space.add(self.drag_body)

    def _place_at_start(self) -> None:
        c, start = self.character, self.scene_spec.start
        angle = math.radians(self.character_spec.start.angle)
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
        space_step, dt = self.space.step, self.dt
        for _ in range(n):
            space_step(dt)
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

    # -- physical parameters ---------------------------------------------------------
    @property
    def gravity(self) -> tuple[float, float]:
        return tuple(self.space.gravity)

    @gravity.setter
    def gravity(self, value: tuple[float, float]) -> None:
        self.space.gravity = value

    # -- state -------------------------------------------------------------------
    def snapshot(self) -> bytes:
        """The whole physical state as bytes (restore with ``restore``)."""
        objects = (self.space, self.character.state_objects(), tuple(self.ground),
                   self.drag_body, self.drag_spring, self.steps)
        return pickle.dumps(objects, protocol=pickle.HIGHEST_PROTOCOL)

    def restore(self, data: bytes) -> None:
        space, character, ground, drag_body, drag_spring, steps = pickle.loads(data)
        self.space = space
        self.character.bind(character)
        self.ground = list(ground)
        self.drag_body, self.drag_spring = drag_body, drag_spring
        self.steps = steps

    def checkpoint(self) -> bytes:
        """Snapshot, and continue from a restored copy so that any later restore of
        this snapshot replays bit-identically to the run that never restored."""
        data = self.snapshot()
        self.restore(data)
        return data

    def state_vector(self) -> list[float]:
        """Position, angle, velocity and angular velocity of every body, in link order."""
        out: list[float] = []
        for name in self.character.link_order:
            b = self.character.bodies[name]
            out += (b.position.x, b.position.y, b.angle, b.velocity.x, b.velocity.y,
                    b.angular_velocity)
        return out

    def state_hash(self) -> str:
        vec = self.state_vector()
        return hashlib.sha256(struct.pack(f"<{len(vec)}d", *vec)).hexdigest()[:16]

    def blown_up(self) -> bool:
        """NaN or runaway velocity anywhere (the state can no longer be trusted)."""
        for b in self.character.bodies.values():
            vx, vy = b.velocity
            w = b.angular_velocity
            x, y = b.position
            if not all(math.isfinite(v) for v in (vx, vy, w, x, y, b.angle)):
                return True
            if vx * vx + vy * vy > MAX_SPEED ** 2 or abs(w) > 50 * MAX_SPEED:
                return True
        return False
