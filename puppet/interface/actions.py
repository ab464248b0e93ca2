"""What a binding does: an interface runtime runs an action (a key's, a state's entry,
the tracker's) part by part, in the order the runtime's docstring gives, and a press or
release of a chord (its binding, a gesture, or a press kept for a later state).

A mixin of ``puppet.interface.runtime.InterfaceRuntime``, which holds the state these
methods write (servos through the character, owners, controllers, state machines)."""

from __future__ import annotations

import math

from puppet.data.actions import ActionSpec
from puppet.interface import meta
from puppet.interface.app_keys import AppAction, SetSlowdown
from puppet.interface.ownership import FRAME
from puppet.interface.poses import frame_target, pose_writer

MAX_CHAINED_GOTOS = 16


_RARE = ("app", "slowdown", "gravity", "friction", "perturb", "push", "track", "kinematic",
         "goto", "over", "sequence", "release", "grasp", "reach")


def _plain(a: ActionSpec) -> bool:
    """An action ``Actions._run_plain`` runs as ``run_action`` would: a mode, gains
    (not while held), a pose and plain angles at most."""
    return all(getattr(a, name) is None for name in _RARE) and not a.while_held \
        and not a.adjust and all(isinstance(v, (int, float)) for v in a.set.values())


class Actions:
    """The actions part of the runtime (see the module docstring)."""

    def _press(self, chord: str, down: bool, now: int, resolved=None):
        """A chord pressed or released; ``resolved``: its owner if already resolved
        at this step (``interface.bindings``), else it is resolved here."""
        if not down:
            self.held.discard(chord)
            restore = self.gain_holds.pop(chord, None)
            if restore:
                servos = self.character.servos
                for joint, (k, d) in restore.items():
                    servos[joint].stiffness, servos[joint].damping = k, d
            return None
        self.held.add(chord)
        if resolved is None:
            resolved = self.resolve(chord)
        binding, machine = resolved.action, resolved.machine
        if binding is None:
            if resolved.gesture:
                self.gestures.start(chord, now)
            else:
                self.buffer.keep(chord, now)
            return None
        self.buffer.spend(chord)
        return self.run_action(binding, now, chord, machine=machine)


    def run_action(self, a: ActionSpec, now: int, chord: str | None = None,
                   depth: int = 0, machine: str | None = None):
        """Run one action (a key's, a state's entry). ``machine``: the state machine the
        action belongs to (its ``goto`` names that machine's states first)."""
        if self._pending:
            self.flush()  # a stream's samples came first: they act first
        if self._kept("_plain_actions", None, a, _plain):
            self._run_plain(a)
            return None
        result = None
        if a.app is not None:
            result = AppAction(a.app)
        if a.slowdown is not None:
            result = SetSlowdown(a.slowdown)
        if self.sim is not None:
            if a.gravity is not None:
                meta.set_gravity(self.sim, a.gravity)
            if a.friction is not None:
                meta.set_friction(self.sim, a.friction)
        if a.perturb is not None:
            self.perturber.switch(a.perturb, now)
        if a.push is not None and self.sim is not None:
            self.sim.push(self.roles.rename(a.push.link), a.push.impulse, a.push.point)
            self.tracker.impact(now)
        if a.track is not None and self.spec.tracking is not None:
            if self._pending:
                self.flush()
            self.tracker.switch(a.track, now)
            for joint in self.tracker.joints:
                self.frames.forget(joint)
        if a.kinematic is not None:
            self.tracker.set_kinematic(a.kinematic)
        if a.mode is not None and a.mode != self.mode:
            self.mode = a.mode
            self._refresh_active_maps()
            self._activate(self.spec.modes[a.mode])
        if a.goto is not None and self.machines:
            to = self.spec.resolve_goto(a.goto, machine)
            if to is not None:
                self._enter_state(to[0], to[1], now, depth)
        servos = self.character.servos
        r = self.roles.rename
        if a.stiffness or a.damping:
            if a.while_held and chord is not None:
                saved = self.gain_holds.setdefault(chord, {})
                for joint in set(a.stiffness) | set(a.damping):
                    saved.setdefault(r(joint), [servos[r(joint)].stiffness,
                                                servos[r(joint)].damping])
            for joint, k in a.stiffness.items():
                servos[r(joint)].stiffness = k
            for joint, d in a.damping.items():
                servos[r(joint)].damping = d
        frames = self.frames
        if a.pose is not None and a.over is None:
            pose = self.poses[a.pose]
            self.owners.take(pose.targets)
            self._pose_writer(pose)(frames, FRAME)  # (apply_pose, its lookups made once)
        held = []
        for joint, deg in ({} if a.over is not None else a.set).items():
            joint = r(joint)
            if isinstance(deg, (int, float)):
                servos[joint].target = math.radians(deg)
                frames.forget(joint)
            else:
                t = frame_target(deg)
                held.append((joint, t if t.ref is None else
                             type(t)(r(t.ref), t.angle, t.hold_parent)))
        for joint, deg in a.adjust.items():
            servos[r(joint)].target += math.radians(deg)
            frames.forget(r(joint))
        self.owners.take([r(j) for j in a.touched_joints()])
        for joint, target in held:  # after the take: a frame target is held (owned)
            frames.hold(joint, target)
        if a.over is not None:  # the pose's and set's targets travel (controllers/blend.py)
            self._blend(a, now)
        if a.sequence is not None:
            self.sequences.start(a.sequence, now, a.repeat)
        if a.release is not None:
            self.release(a.release)
        if a.grasp is not None:
            self.grasping.arm(a.grasp, now)
        if a.reach is not None:
            self.reaching.start(a.reach, now)
        return result

    def _run_plain(self, a: ActionSpec) -> None:
        """``run_action`` of an action that is a mode, gains, a pose and plain angles at
        most (``_plain``: a gait's state entry, several a second): its parts in the same
        order, without asking for each part it has not."""
        if a.mode is not None and a.mode != self.mode:
            self.mode = a.mode
            self._refresh_active_maps()
            self._activate(self.spec.modes[a.mode])
        servos = self.character.servos
        r = self.roles.rename
        if a.stiffness or a.damping:
            for joint, k in a.stiffness.items():
                servos[r(joint)].stiffness = k
            for joint, d in a.damping.items():
                servos[r(joint)].damping = d
        frames = self.frames
        if a.pose is not None:
            pose = self.poses[a.pose]
            self.owners.take(pose.targets)
            self._pose_writer(pose)(frames, FRAME)
        if a.set:
            for joint, deg in a.set.items():
                joint = r(joint)
                servos[joint].target = math.radians(deg)
                frames.forget(joint)
            self.owners.take([r(j) for j in a.touched_joints()])

    def _pose_writer(self, pose):
        """``poses.pose_writer`` for ``pose``, kept while the springs stay bound."""
        servos = self.character.servos
        return self._kept("_pose_writers", self.character.bodies, pose,
                          lambda p: pose_writer(servos, p))

    def _kept(self, name: str, bound, thing, make):
        """``make(thing)``, kept in the table ``name`` by the thing's identity (each
        entry holds its thing, so an id stays its own), the table started afresh when
        ``bound`` (what the made values hold on to) is another object."""
        table = self.__dict__.get(name)
        if table is None or table[0] is not bound:
            table = self.__dict__[name] = (bound, {})
        got = table[1].get(id(thing))
        if got is None or got[0] is not thing:
            got = table[1][id(thing)] = (thing, make(thing))
        return got[1]

    def _blend(self, a: ActionSpec, now: int) -> None:
        """An action's pose and set with ``over``: the targets travel (its gains now)."""
        pose = self.poses[a.pose] if a.pose is not None else None
        self.blends.start_action(pose, a.set, self.roles.rename, now, round(a.over / self.dt))

    def release(self, which: str) -> None:
        """Let go: unpin the chain ("all": every chain) and disarm its grasp, also
        a running reach's."""
        self.grasping.release(which)
        self.reaching.let_go(which)

    def _enter_state(self, machine: str, state: str, now: int, depth: int) -> None:
        if depth >= MAX_CHAINED_GOTOS:
            return
        self.machines[machine].enter(state, now)
        self._follow_rate()  # a state may ask for faster control steps
        roles = self.machines[machine].spec.states[state].roles
        rebound = roles is not None and roles != self.role_binding
        if rebound:
            self._use_binding(roles)
        self._refresh_active_maps()
        if rebound:  # a device map on a role now means another joint: it acts there
            self._activate(self._role_maps())
        self._activate(self.machines[machine].spec.states[state].maps)
        self._run_entry(machine, now, depth + 1)
        if self.buffer.unused and self.machines[machine].current == state:
            due = self.buffer.due(self._lookup, now)  # a press kept for this state
            if due is not None:
                self.run_action(due[0], now, due[2], depth + 1, due[1])

    def _run_entry(self, machine: str, now: int, depth: int) -> None:
        m = self.machines[machine]
        enter = m.spec.states[m.current].enter
        if enter is not None:
            self.run_action(enter, now, None, depth, machine)


    def _tracking_due(self, now: int) -> None:
        """Run what the tracker asked for: ``tracking.lost`` (the stream is lost: the
        interface's balance), ``found`` (it is back), ``reaction.get_up`` (a fall)."""
        due, self.tracker.due = self.tracker.due, []
        spec = self.spec.tracking
        for what in due:
            action = (spec.reaction.get_up if what == "get_up" and spec.reaction is not None
                      else getattr(spec, what, None) if what != "get_up" else None)
            if action is not None:
                self.run_action(action, now)


    def _gains_of(self, name: str) -> tuple[float, float, float]:
        """(stiffness, damping, max torque) the interface gives a joint's servo, each
        the character's where the interface says nothing."""
        k, d, t = self.character.servos[name].default_gains
        gain = self.spec.gains.get(name)
        if gain is not None:
            k = gain.stiffness if gain.stiffness is not None else k
            d = gain.damping if gain.damping is not None else d
            t = gain.max_torque if gain.max_torque is not None else t
        return k, d, t

    def apply_gains(self) -> None:
        """Interface gains override the character's defaults."""
        for name, servo in self.character.servos.items():
            servo.stiffness, servo.damping, servo.max_torque = self._gains_of(name)

    def restore_gains(self, joints) -> None:
        """The interface's gains (else the character's) back on ``joints``."""
        servos = self.character.servos
        for name in joints:
            servos[name].stiffness, servos[name].damping, _ = self._gains_of(name)
