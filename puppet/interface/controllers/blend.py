"""Poses reached over time: a pose or `set` with ``over: SECONDS`` moves each target from
where it is to where the pose puts it along an eased path, at the control rate.

Why: a target that jumps makes a light, lightly damped limb snap at full torque, and
heavy damping (which keeps a jump of target gentle) acts per simulation step, so the
same move then runs at another speed with another step length. A target that travels
over a time is the same path at any step length, and lets the joints stay lightly
damped. The path is the reach's ease (slow, fast, slow: smoothstep) over whole steps
from the start, so a replay is bit-identical, and the targets are written on steps
that are multiples of the control period (absolute, as frame targets are solved).

A plain joint target travels from the servo's target when the action ran; a target in
another frame (``{world: A}``, ``relative_to``) travels from the angle that link has in
that frame then, and is held by the frame-target controller all the way (re-solved
from the figure's state), and afterwards, as an instant pose's frame target is. The
joints are owned under BLEND while they travel: a later pose, set, adjust or map on a
joint takes it back, as from a sequence; its other joints go on.
"""

from __future__ import annotations

import math

from pymunk._chipmunk_cffi import lib as _cp

from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import BLEND, JointOwners, Owner
from puppet.interface.poses import (
    FrameTarget,
    Pose,
    apply_pose,
    frame_target,
    made_frame_target,
)
from puppet.physics.servo import SET_TARGET

_angle = _cp.cpBodyGetAngle
_set_target = SET_TARGET


class BlendController:
    BUSY = "moving"

    def __init__(self, character, owners: JointOwners, frames, every: int):
        self.character = character
        self.owners_table = owners
        self.frames = frames
        self.every = every
        self.joints = {j.name: j for j in character.spec.actuated}
        # joint -> [from, to, first step, last step, frame target or None]: a frame
        # target's angle travels, a plain target's value does
        self.moving: dict[str, list] = {}

    def start(self, targets: dict[str, float], frames: dict[str, FrameTarget], now: int,
              steps: int) -> None:
        """Move ``targets`` (joint -> rad) and ``frames`` (joint -> FrameTarget) there
        over ``steps`` steps from ``now``; the joints are taken (an instant write)."""
        servos = self.character.servos
        self.owners_table.take(list(targets) + list(frames))
        end = now + max(1, steps)
        for joint, to in targets.items():
            self.frames.forget(joint)
            self.moving[joint] = [servos[joint].target, to, now, end, None]
        for joint, target in frames.items():
            self.moving[joint] = [self._frame_angle(joint, target), target.angle, now, end,
                                  target]
        self.owners_table.claim(list(targets) + list(frames), BLEND)
        self._write(now)

    def start_action(self, pose: Pose | None, set_targets: dict, rename, now: int,
                     steps: int) -> None:
        """An action's ``pose`` (compiled) and ``set`` (degrees or frame targets, as the
        file has them; ``rename`` binds roles) reached over ``steps`` steps: the pose's
        gains are written at once, the set's targets win over the pose's."""
        targets, frames = {}, {}
        if pose is not None:
            apply_pose(self.character.servos, Pose({}, pose.stiffness, pose.damping, {},
                                                   pose.max_torque))
            targets.update(pose.targets)
            frames.update(pose.frames)
        for joint, value in set_targets.items():
            joint = rename(joint)
            targets.pop(joint, None)
            frames.pop(joint, None)
            if isinstance(value, (int, float)):
                targets[joint] = math.radians(value)
            else:
                t = frame_target(value)
                frames[joint] = t if t.ref is None else FrameTarget(rename(t.ref), t.angle,
                                                                    t.hold_parent)
        self.start(targets, frames, now, steps)

    def _frame_angle(self, joint: str, target: FrameTarget) -> float:
        """The angle ``target`` names, as the figure has it now (its ref frame, the
        child or the parent link): where its travel starts, in the same turn as the
        target's angle."""
        bodies = self.character.bodies
        spec = self.joints[joint]
        link = spec.parent if target.hold_parent else spec.child
        now = _angle(bodies[link]._body)
        if target.ref is not None:
            now -= _angle(bodies[target.ref]._body)
        return target.angle + math.remainder(now - target.angle, 2.0 * math.pi)

    def _write(self, step: int) -> bool:
        """Write the travelling targets at ``step``; True when that was all: plain
        targets only, none arrived or taken back (the schedule stands)."""
        table = self.owners_table.table
        servos = self.character.servos
        moving = self.moving
        plain = True
        for joint, m in tuple(moving.items()):
            if table.get(joint) != BLEND:  # taken back by a later write
                del moving[joint]
                plain = False
                continue
            start, to, first, last, target = m
            if step >= last:
                u = 1.0
            else:  # eased: smoothstep, u^2 (3 - 2u)
                u = (step - first) / (last - first)
                u = u * u * (3.0 - 2.0 * u)
            value = start + (to - start) * u
            if target is None:
                _set_target(servos[joint].spring._constraint, value)  # servo.target =
            else:
                plain = False
                self.frames.hold(joint, made_frame_target(target.ref, value, target.hold_parent),
                                 BLEND)
            if step >= last:  # arrived: a plain target stays, a frame target is held on
                plain = False
                del moving[joint]
                if target is None:
                    del table[joint]
                else:
                    self.frames.hold(joint, target)  # under FRAME, as an instant pose's
        return plain

    def tick(self, step: int) -> str | None:
        if step % self.every:
            if not any(step >= m[3] for m in self.moving.values()):
                return WAITED  # between control steps, nothing arriving
            self._write(step)
            return None
        if self._write(step) and self.every == 1:
            return WAITED  # at every step, plain targets only, none arrived: the next
        return None  # wake-up is the next step, the arbiter's schedule (base.WAITED)

    def next_wakeup(self, earliest: int) -> int | None:
        moving = self.moving
        if not moving:
            return None
        every = self.every
        tick = -(-earliest // every) * every
        arrive = None  # the first arrival, not before ``earliest``
        for m in moving.values():
            if arrive is None or m[3] < arrive:
                arrive = m[3]
        if arrive < earliest:
            arrive = earliest
        return tick if tick <= arrive else arrive

    def owners(self) -> set[Owner]:
        return {BLEND} if self.moving else set()

    def get_state(self):
        return {j: [a, b, s, e, None if t is None else t.to_state()]
                for j, (a, b, s, e, t) in self.moving.items()}

    def set_state(self, state) -> None:
        self.moving = {j: [a, b, s, e, None if t is None else FrameTarget(*t)]
                       for j, (a, b, s, e, t) in state.items()}

    def adopt(self, old: BlendController, same, now: int) -> set[Owner]:
        """A hot reload ends the travel: the joints keep the targets they have."""
        return set()

    def stop(self) -> None:
        self.moving = {}

