"""Targets in another frame: a joint held so that one of its links keeps an angle in
the world, or relative to another link ("the chest 5 degrees forward of vertical,
held by the stance hip"), re-solved from the figure's state at the control rate.

A frame target is written by a pose, a set or a map like any target, so the owner
table decides who may write the joint: an instant write holds it under the FRAME
owner (a later write takes it back, as from a sequence); a sequence's pose holds it
under the sequence. The re-solve runs on steps that are multiples of the control
period (absolute, so replays split their steps any way and agree).
"""

from __future__ import annotations

import math

from pymunk._chipmunk_cffi import lib as _cp

from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import FRAME, JointOwners, Owner
from puppet.interface.poses import FrameTarget
from puppet.physics import kernel as _kernel
from puppet.physics.servo import SET_TARGET as _set_target

_TURN = 2.0 * math.pi
_remainder = _kernel.remainder  # (as C's answers a blown-up state: pk_frame)
_angle = _cp.cpBodyGetAngle
_new = object.__new__


class FrameTargets:
    BUSY = "held"

    def __init__(self, character, owners: JointOwners, every: int):
        self.character = character
        self.owners_table = owners
        self.every = every
        self.held: dict[str, tuple[FrameTarget, Owner]] = {}  # joint -> (target, owner)
        self.joints = {j.name: j for j in character.spec.actuated}
        # the compiled kernel's solve (``pk_frame``: the same arithmetic in C), or None
        # (PUPPET_KERNEL=python); its pointers: joint -> (parent, child, spring) and
        # link -> body, for the bodies they were taken from (a restore re-binds them)
        kern = _kernel.get()
        self._kernel = kern
        self._pk_frame = None if kern is None else kern.lib.pk_frame
        self._null = None if kern is None else kern.ffi.NULL
        self._bound = None
        self._joint_ptrs: dict = {}
        self._link_ptrs: dict = {}
        # joint -> (its held target, pk_frame's arguments for it): made once per target
        # (a hold makes a new one) and per binding of the bodies (``_pointers``)
        self._args: dict = {}

    def hold(self, joint: str, target: FrameTarget, owner: Owner | None = None) -> None:
        """Hold ``joint`` at ``target`` from now on (solved at once, then at the control
        rate) under ``owner`` (default FRAME: an instant write, which claims it)."""
        owner = owner or FRAME
        if owner == FRAME:
            self.owners_table.table[joint] = FRAME
        self.held[joint] = (target, owner)
        self._solve(joint, target)

    def holder(self, joint: str, ref: str | None, hold_parent: bool,
               owner: Owner | None = None):
        """``hold_at(angle)``: ``hold(joint, FrameTarget(ref, angle, hold_parent), owner)``
        for a frame map, which holds its joints at every mouse event: the target made
        without the dataclass's ``__init__`` (as ``poses.made_frame_target``) and the
        kernel's pointers for the joint looked up once per binding of the bodies."""
        owner = owner or FRAME
        claim = owner == FRAME
        solve, null, new = self._pk_frame, self._null, _new
        bound: list = [None, None]  # the bodies, and pk_frame's pointers into them

        def hold_at(angle: float) -> None:
            if claim:
                self.owners_table.table[joint] = FRAME
            target = new(FrameTarget)
            fields = target.__dict__
            fields["ref"], fields["angle"], fields["hold_parent"] = ref, angle, hold_parent
            self.held[joint] = (target, owner)
            if solve is None:
                self._solve(joint, target)
                return
            if bound[0] is not self.character.bodies:
                joint_ptrs, link_ptrs = self._pointers()
                parent, child, spring = joint_ptrs.get(joint) or self._joint_ptr(joint)
                bound[:] = self._bound, (parent, child, null if ref is None else
                                         (link_ptrs.get(ref) or self._link_ptr(ref)), spring)
            parent, child, link, spring = bound[1]
            args = (parent, child, link, angle, hold_parent, spring)
            self._args[joint] = (target, args)
            solve(*args)
        return hold_at

    def forget(self, joint: str) -> None:
        self.held.pop(joint, None)

    def _pointers(self) -> tuple[dict, dict]:
        """The kernel's pointers (empty tables, filled by ``_joint_ptr`` and
        ``_link_ptr``, when the character's bodies were re-bound)."""
        bodies = self.character.bodies
        if self._bound is not bodies:
            self._bound, self._joint_ptrs, self._link_ptrs = bodies, {}, {}
            self._args = {}
        return self._joint_ptrs, self._link_ptrs

    def _joint_ptr(self, joint: str) -> tuple:
        c, spec, pointer = self.character, self.joints[joint], self._kernel.pointer
        got = self._joint_ptrs[joint] = (
            pointer(c.bodies[spec.parent]._body), pointer(c.bodies[spec.child]._body),
            pointer(c.servos[joint].spring._constraint))
        return got

    def _link_ptr(self, link: str):
        got = self._link_ptrs[link] = self._kernel.pointer(self.character.bodies[link]._body)
        return got

    def _prepared(self, joint: str, target: FrameTarget) -> tuple:
        """pk_frame's arguments for holding ``joint`` at ``target`` (on the bodies of
        now)."""
        joint_ptrs, link_ptrs = self._pointers()
        parent, child, spring = joint_ptrs.get(joint) or self._joint_ptr(joint)
        ref = target.ref
        return (parent, child, self._null if ref is None else
                (link_ptrs.get(ref) or self._link_ptr(ref)), target.angle,
                target.hold_parent, spring)

    def _solve(self, joint: str, target: FrameTarget) -> None:
        if self._pk_frame is not None:  # the kernel: the arithmetic below, in C
            if self._bound is not self.character.bodies:
                self._pointers()  # (re-bound: the prepared arguments go)
            got = self._args.get(joint)
            if got is None or got[0] is not target:  # (a pose's targets are kept: made once)
                got = self._args[joint] = (target, self._prepared(joint, target))
            self._pk_frame(*got[1])
            return
        # (angles through pymunk's own C call, what Body.angle returns: this runs for
        # every held joint at every control step)
        c = self.character
        bodies = c.bodies
        spec = self.joints[joint]
        parent = _angle(bodies[spec.parent]._body)
        child = _angle(bodies[spec.child]._body)
        want = target.angle + (0.0 if target.ref is None else _angle(bodies[target.ref]._body))
        if target.hold_parent:  # the parent at ``want``: child - want
            q = child - want
        else:  # the child at ``want``: want - parent
            q = want - parent
        now = child - parent  # the same turn as the joint is in now
        _set_target(c.servos[joint].spring._constraint, now + _remainder(q - now, _TURN))

    def tick(self, step: int) -> str | None:
        if step % self.every:
            return WAITED  # between control steps
        table, held = self.owners_table.table, self.held
        solve = self._pk_frame
        let_go = False
        if solve is not None:  # the kernel: the Python loop below, each joint in C
            if self._bound is not self.character.bodies:
                self._pointers()  # (re-bound: the prepared arguments go)
            prepared = self._args
            gone = None
            for joint, (target, owner) in held.items():
                if table.get(joint) != owner:  # taken back by a later write: let go
                    if gone is None:
                        gone = []
                    gone.append(joint)
                    continue
                got = prepared.get(joint)
                if got is None or got[0] is not target:
                    got = prepared[joint] = (target, self._prepared(joint, target))
                solve(*got[1])
            if gone is not None:
                for joint in gone:
                    del held[joint]
                let_go = True
            # at every step (control_rate: 480), still holding and none let go: it only
            # wrote targets, and its next wake-up is the next step (base.WAITED)
            return WAITED if self.every == 1 and held and not let_go else None
        c = self.character
        bodies, servos, joints = c.bodies, c.servos, self.joints
        remainder = _remainder
        for joint, (target, owner) in list(held.items()):
            if table.get(joint) != owner:  # taken back by a later write: let go
                del held[joint]
                let_go = True
                continue
            spec = joints[joint]  # _solve's arithmetic, inlined (a tick holds several)
            parent = _angle(bodies[spec.parent]._body)
            child = _angle(bodies[spec.child]._body)
            ref = target.ref
            want = target.angle + (0.0 if ref is None else _angle(bodies[ref]._body))
            q = child - want if target.hold_parent else want - parent
            now = child - parent
            _set_target(servos[joint].spring._constraint, now + remainder(q - now, _TURN))
        return WAITED if self.every == 1 and held and not let_go else None

    def next_wakeup(self, earliest: int) -> int | None:
        if not self.held:
            return None
        return -(-earliest // self.every) * self.every

    def owners(self) -> set[Owner]:
        return {FRAME} if any(o == FRAME for _, o in self.held.values()) else set()

    def get_state(self):
        return {j: [t.to_state(), o.kind, o.name] for j, (t, o) in self.held.items()}

    def set_state(self, state) -> None:
        self.held = {j: (FrameTarget(*t), Owner(kind, name))
                     for j, (t, kind, name) in state.items()}

    def adopt(self, old: FrameTargets, same, now: int) -> set[Owner]:
        self.held = dict(old.held)
        return self.owners()

    def stop(self) -> None:
        self.held = {}
