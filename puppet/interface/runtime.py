"""Run an interface file: input events in, PD targets and gains out.

The runtime is event driven: targets change when an input changes, so between
events the physics steps at full speed with nothing to do in Python. Time-driven
work (pose sequences, reaches, armed grasps, state timers and conditions,
perturbations) announces itself through ``next_wakeup``, the sim step at which
``tick`` must next run; ``None`` means idle, and the session then steps the physics
in one tight loop.

Arbitration - who writes a joint's target - follows "the most recent action wins",
per joint:
  * a running sequence or reach *owns* the joints it drives;
  * a new sequence replaces the running sequence entirely; a new reach replaces the
    running reach of the same chain; either takes its joints from the other;
  * a pose, set or adjust (key, or state entry) and a continuous map that updates
    (its input changed, or its mode/state became active) take the joints they write
    back from any sequence or reach, which carries on with its remaining joints and
    ends when it has none;
  * gains (stiffness/damping) are not owned: the latest write wins.
An action's parts run in this order, later ones winning on shared joints: app/meta
(slowdown, gravity, friction, perturb), mode, goto (the new state's maps, then its
``enter`` action), stiffness/damping, pose, set, adjust, sequence, release, grasp,
reach.
"""

from __future__ import annotations

import math

import pymunk

from puppet.data.actions import ActionSpec
from puppet.data.interfaces import InterfaceSpec
from puppet.interface import maps as mapping
from puppet.interface import meta, sequences
from puppet.interface.app_keys import normalize_key
from puppet.interface.events import Event, is_analog
from puppet.interface.ik import Chain, Reach
from puppet.interface.poses import apply_pose, compile_poses
from puppet.interface.state_machine import StateMachine
from puppet.physics.character import Character

SEQ = "seq"
GESTURE = "gesture"
MAX_CHAINED_GOTOS = 16


class InterfaceRuntime:
    def __init__(self, spec: InterfaceSpec, character: Character, sim=None,
                 dt: float | None = None, start: bool = True):
        """``start=False``: touch no servo (no gains, no state entry); the caller then
        gives the runtime its state (``set_state`` from a snapshot, or ``adopt``)."""
        self.spec = spec
        self.character = character
        self.sim = sim
        self.dt = dt if dt is not None else (sim.dt if sim is not None else 1.0 / 480.0)
        self.now = 0  # current step when there is no Simulation to ask
        self.poses = compile_poses(spec.poses)
        self.pose_targets = {n: p.targets for n, p in self.poses.items()}
        self.plans = sequences.compile_sequences(spec.sequences, self.dt)
        self.bindings = {normalize_key(k.key): k for k in spec.keys}
        # key -> [(step offset, x, y)]: recorded mouse paths, replayed in sim time
        self.gestures = {normalize_key(g.key): [(round(t / self.dt), x, y) for t, x, y in g.path]
                         for g in spec.gestures}
        self.state_bindings = {name: {normalize_key(k.key): k for k in s.keys}
                               for name, s in spec.states.items()}
        self.chains = {n: Chain.from_spec(n, c, character.spec) for n, c in spec.chains.items()}
        self.machine = StateMachine(spec, character, self.dt) if spec.states else None
        self.perturber = meta.Perturber(spec.perturbation, self.dt)
        self.inputs: dict[str, float] = {}
        self.held: set[str] = set()
        self.next_wakeup: int | None = None
        self._map_cache: dict[int, object] = {}
        self._clear_activity()
        if start:
            self.apply_gains()
            self._start_control()

    def adopt(self, old: InterfaceRuntime) -> None:
        """Take over from ``old``, the runtime of the interface this one replaces (a hot
        reload): the physics and the servo targets stay as they are, so nothing moves
        until an input changes or a key is pressed; input values and held keys carry
        over; so does what is running (sequence, reaches, grasps, gain holds, state,
        mode, perturbation) where the new interface defines it the same way. The rest
        ends, leaving its joints' targets where they are."""
        now = old.step_now()
        self.now = old.now
        self.inputs = dict(old.inputs)
        self.held = set(old.held)
        spec, was = self.spec, old.spec
        self.mode = old.mode if old.mode in spec.modes else spec.start_mode
        kept: set[str] = set()
        seq = old.sequence
        if (seq is not None and seq.name in spec.sequences
                and spec.sequences[seq.name] == was.sequences.get(seq.name)
                and all(spec.poses.get(p.pose) == was.poses.get(p.pose)
                        for p in spec.sequences[seq.name])):
            self.sequence = sequences.RunningSequence.from_state(seq.to_state())
            kept.add(SEQ)
        g = old.gesture
        if g is not None and self.gestures.get(g[0]) == old.gestures.get(g[0]):
            self.gesture = list(g)
            kept.add(GESTURE)
        same_chain = {n for n in old.chains if n in spec.chains
                      and spec.chains[n] == was.chains[n]}
        for name, reach in old.reaches.items():
            if name in same_chain:
                self.reaches[name] = Reach.from_state(reach.to_state())
                kept.add(f"reach:{name}")
        self.grasps = _copy_grasps({n: g for n, g in old.grasps.items() if n in same_chain})
        for name in list(old.grasped):
            if name in same_chain:
                self.grasped[name] = list(old.grasped[name])
            else:
                old.release(name)  # its chain is gone or changed: let go
        self.owner = {j: tag for j, tag in old.owner.items() if tag in kept}
        if spec.gains == was.gains:
            self.gain_holds = _copy_holds(old.gain_holds)
        else:
            self.apply_gains()
        if spec.perturbation == was.perturbation:
            self.perturber.set_state(old.perturber.get_state())
        elif old.perturber.on:
            self.perturber.switch("on", now)
        if self.machine is not None:
            if old.machine is not None and old.machine.current in spec.states:
                self.machine.set_state(old.machine.get_state())
                self._refresh_active_maps()
            else:  # a new state machine (or the state is gone): start it
                self._start_control()
                return
        else:
            self._refresh_active_maps()
        self._reschedule(now)

    # -- bookkeeping -------------------------------------------------------------
    def _clear_activity(self) -> None:
        self.mode = self.spec.start_mode
        self.owner: dict[str, str] = {}  # joint -> "seq" or "reach:<chain>"
        self.sequence: sequences.RunningSequence | None = None
        self.gesture: list | None = None  # [key, start step, index of the next point]
        self.reaches: dict[str, Reach] = {}
        self.grasps: dict[str, list] = {}  # chain -> [points, tolerance, until step|None]
        self.grasped: dict[str, list[float]] = {}  # chain -> world point held
        self.gain_holds: dict[str, dict[str, list[float]]] = {}  # chord -> joint -> [k, d]

    def _start_control(self) -> None:
        now = self.step_now()
        if self.machine is not None:
            self.machine.enter(self.machine.initial, now)
        self._refresh_active_maps()
        if self.machine is not None:
            enter = self.spec.states[self.machine.current].enter
            if enter is not None:
                self.run_action(enter, now)
        self._reschedule(now)

    def step_now(self) -> int:
        return self.sim.steps if self.sim is not None else self.now

    @property
    def state(self) -> str | None:
        """The state machine's current state (None without states)."""
        return self.machine.current if self.machine is not None else None

    def _refresh_active_maps(self) -> None:
        active = list(self.spec.maps)
        if self.mode is not None:
            active += self.spec.modes[self.mode]
        if self.machine is not None:
            active += self.spec.states[self.machine.current].maps
        self.active_maps = active
        self._mouse_maps = self._compiled(("mouse.x", "mouse.y"))
        joints: set[str] = set()
        for m in active:
            if "mouse.x" in m.inputs or "mouse.y" in m.inputs:
                if getattr(m, "grid", None) is not None:
                    these = {j for row in m.grid for p in row for j in self.pose_targets[p]}
                    joints |= these if m.joints is None else these & set(m.joints)
                else:
                    joints |= set(m.gains())
        self._mouse_joints = joints  # what a gesture drives

    def _compiled(self, inputs) -> list:
        """Compiled appliers of the active maps reading any of ``inputs``, in order."""
        return [self._applier(m) for m in self.active_maps
                if any(i in inputs for i in m.inputs)]

    def _applier(self, m):
        """The compiled form of map ``m`` (compiled once per runtime)."""
        applier = self._map_cache.get(id(m))
        if applier is None:
            applier = self._map_cache[id(m)] = mapping.compile_map(
                m, self.character.servos, self.pose_targets)
        return applier

    def pointer_for_pose(self, tolerance_deg: float = 2.0) -> tuple[float, float] | None:
        """The mouse position (x, y in 0..1) at which the active mouse maps give the
        targets the joints have now (at the start: the start pose), or None if no
        position comes within ``tolerance_deg`` on every joint they drive. The window
        puts the pointer there when it opens, so its first mouse event does not snap
        the character out of its pose (the middle of luxo-mouse throws Luxo over).
        A grid search, then a pattern search; the targets are left as they were."""
        if not self._mouse_maps or not self._mouse_joints:
            return None
        servos = self.character.servos
        want = {j: servos[j].target for j in self._mouse_joints}
        values = dict(self.inputs)

        def score(x: float, y: float) -> tuple[float, float]:
            values["mouse.x"], values["mouse.y"] = x, y
            for apply in self._mouse_maps:
                apply(values)  # written straight to the servos; put back below
            error = max(abs(servos[j].target - t) for j, t in want.items())
            return error, abs(x - 0.5) + abs(y - 0.5)  # ties: nearer the middle

        try:
            n = 20
            best, x, y = min((score(i / n, k / n), i / n, k / n)
                             for i in range(n + 1) for k in range(n + 1))
            step = 1.0 / n
            while step > 1e-4:
                moves = [(min(1.0, max(0.0, x + dx * step)), min(1.0, max(0.0, y + dy * step)))
                         for dx in (-1, 0, 1) for dy in (-1, 0, 1) if dx or dy]
                found = min((score(*p), *p) for p in moves)
                if found[0] < best:
                    best, x, y = found
                else:
                    step /= 2
        finally:
            for joint, target in want.items():
                servos[joint].target = target
        return (x, y) if best[0] <= math.radians(tolerance_deg) else None

    def apply_gains(self) -> None:
        """Interface gains override the character's defaults."""
        for name, servo in self.character.servos.items():
            k, d, t = servo.default_gains
            gain = self.spec.gains.get(name)
            if gain is not None:
                k = gain.stiffness if gain.stiffness is not None else k
                d = gain.damping if gain.damping is not None else d
                t = gain.max_torque if gain.max_torque is not None else t
            servo.stiffness, servo.damping, servo.max_torque = k, d, t

    # -- input -------------------------------------------------------------------
    def binding(self, chord: str) -> ActionSpec | None:
        """The action bound to a chord in the current state (state keys first)."""
        if self.machine is not None:
            found = self.state_bindings[self.machine.current].get(chord)
            if found is not None:
                return found
        return self.bindings.get(chord)

    def handles_key(self, chord: str) -> bool:
        return self.binding(chord) is not None or chord in self.gestures

    def on_event(self, event: Event) -> str | None:
        """Apply an input event at the current step. Returns an app action the event
        asks for (e.g. "pause", "slowdown:10"), for the session to perform or pass on."""
        kind = event["type"]
        if kind == "mouse":
            self.inputs["mouse.x"] = event["x"]
            self.inputs["mouse.y"] = event["y"]
            values, owner = self.inputs, self.owner
            for apply in self._mouse_maps:  # the hot path: no lookups, no allocation
                written = apply(values)
                if owner:
                    self._take(written)
            # Maps write targets and take joints; nothing that sets a wake-up changes
            # (an emptied sequence or gesture ends at its own next wake-up).
            return None
        now = self.step_now()
        result = None
        if kind == "key":
            result = self._press(event["key"], event["down"], now)
        elif kind in ("mouse_button", "gamepad", "channel"):
            if kind == "mouse_button":
                name, value = f"mouse.{event['button']}", 1.0 if event["down"] else 0.0
            elif kind == "gamepad":
                name, value = f"gamepad.{event['name']}", float(event["value"])
            else:
                name, value = f"channel.{event['name']}", float(event["value"])
            was = self.inputs.get(name, 0.0)
            self.inputs[name] = value
            self.apply_maps((name,))
            if kind != "channel" and not is_analog(name) \
                    and (was > 0.5) != (value > 0.5):  # buttons also act as keys
                result = self._press(name, value > 0.5, now)
        else:
            return None
        self._reschedule(now)
        return result

    def _press(self, chord: str, down: bool, now: int) -> str | None:
        if not down:
            self.held.discard(chord)
            restore = self.gain_holds.pop(chord, None)
            if restore:
                servos = self.character.servos
                for joint, (k, d) in restore.items():
                    servos[joint].stiffness, servos[joint].damping = k, d
            return None
        self.held.add(chord)
        binding = self.binding(chord)
        if binding is None:
            if chord in self.gestures:
                self._start_gesture(chord, now)
            return None
        return self.run_action(binding, now, chord)

    def apply_maps(self, inputs=None) -> None:
        """Re-evaluate the active maps that read ``inputs`` (default: all inputs)."""
        inputs = self.inputs.keys() if inputs is None else inputs
        for apply in self._compiled(set(inputs)):
            self._take(apply(self.inputs))

    def _activate(self, maps) -> None:
        """Maps that just became active (a mode or state entered) act at once with the
        inputs as they are; the maps that were active already leave their joints be."""
        for m in maps:
            self._take(self._applier(m)(self.inputs))

    # -- actions -----------------------------------------------------------------
    def _take(self, joints) -> None:
        """Instant writes take joints back from sequences and reaches."""
        if self.owner:
            for joint in joints:
                self.owner.pop(joint, None)

    def run_action(self, a: ActionSpec, now: int, chord: str | None = None,
                   depth: int = 0) -> str | None:
        result = None
        if a.app is not None:
            result = a.app
        if a.slowdown is not None:
            result = f"slowdown:{a.slowdown:g}"
        if self.sim is not None:
            if a.gravity is not None:
                meta.set_gravity(self.sim, a.gravity)
            if a.friction is not None:
                meta.set_friction(self.sim, a.friction)
        if a.perturb is not None:
            self.perturber.switch(a.perturb, now)
        if a.mode is not None and a.mode != self.mode:
            self.mode = a.mode
            self._refresh_active_maps()
            self._activate(self.spec.modes[a.mode])
        if a.goto is not None and self.machine is not None:
            self._enter_state(a.goto, now, depth)
        servos = self.character.servos
        if a.stiffness or a.damping:
            if a.while_held and chord is not None:
                saved = self.gain_holds.setdefault(chord, {})
                for joint in set(a.stiffness) | set(a.damping):
                    saved.setdefault(joint, [servos[joint].stiffness, servos[joint].damping])
            for joint, k in a.stiffness.items():
                servos[joint].stiffness = k
            for joint, d in a.damping.items():
                servos[joint].damping = d
        if a.pose is not None:
            pose = self.poses[a.pose]
            apply_pose(servos, pose)
            self._take(pose.targets)
        for joint, deg in a.set.items():
            servos[joint].target = math.radians(deg)
        for joint, deg in a.adjust.items():
            servos[joint].target += math.radians(deg)
        self._take(a.touched_joints())
        if a.sequence is not None:
            self._start_sequence(a.sequence, now)
        if a.release is not None:
            self.release(a.release)
        if a.grasp is not None:
            g = a.grasp
            until = None if g.within is None else now + round(g.within / self.dt)
            self.grasps[g.chain] = [[list(p) for p in g.points], g.tolerance, until]
        if a.reach is not None:
            self._start_reach(a.reach, now)
        return result

    def _enter_state(self, name: str, now: int, depth: int) -> None:
        if depth >= MAX_CHAINED_GOTOS:
            return
        self.machine.enter(name, now)
        self._refresh_active_maps()
        self._activate(self.spec.states[name].maps)
        enter = self.spec.states[name].enter
        if enter is not None:
            self.run_action(enter, now, None, depth + 1)

    def _start_sequence(self, name: str, now: int) -> None:
        self._drop(SEQ)
        self.sequence = sequences.start(self.plans, name, now)
        joints = set()
        for pose_name, _ in self.plans[name]:
            joints |= self.poses[pose_name].joints
        for joint in joints:
            self.owner[joint] = SEQ
        apply_pose(self.character.servos, self.poses[self.plans[name][0][0]])

    # -- gestures --------------------------------------------------------------------
    def _start_gesture(self, chord: str, now: int) -> None:
        """Play a recorded mouse path: it owns the joints the active mouse maps drive
        (taken back like a sequence's: by a pose, a moving mouse, a new sequence)."""
        self._drop(GESTURE)
        for joint in self._mouse_joints:
            self.owner[joint] = GESTURE
        self.gesture = [chord, now, 0]
        self._play_gesture(now)

    def _play_gesture(self, step: int) -> None:
        """Feed the gesture's points due by ``step`` through the mouse maps, writing
        only the joints it still owns; end it when done or when it owns none."""
        chord, start, index = self.gesture
        path = self.gestures[chord]
        owned = {j for j, o in self.owner.items() if o == GESTURE}
        if owned:
            servos = self.character.servos
            others = [(servos[j], servos[j].target) for j in self._mouse_joints - owned]
            values = dict(self.inputs)
            while index < len(path) and start + path[index][0] <= step:
                values["mouse.x"], values["mouse.y"] = path[index][1], path[index][2]
                for apply in self._mouse_maps:
                    apply(values)
                index += 1
            for servo, target in others:  # joints taken back by later actions
                servo.target = target
        if index >= len(path) or not owned:
            self._drop(GESTURE)
            self.gesture = None
        else:
            self.gesture[2] = index

    def _start_reach(self, r, now: int) -> None:
        chain = self.chains[r.chain]
        tag = f"reach:{r.chain}"
        self._drop(tag)
        if r.frame == "root":
            root = self.character.bodies[self.character.spec.root]
            p = root.local_to_world(r.target)
            target = (p[0], p[1])
        else:
            target = tuple(r.target)
        steps = max(1, round(r.duration / self.dt))
        self.reaches[r.chain] = Reach(r.chain, chain.end_world(self.character), target, now,
                                      steps, now + steps + round(r.hold / self.dt),
                                      r.grasp, r.tolerance)
        for joint in chain.joints:
            self.owner[joint] = tag

    def _drop(self, tag: str) -> None:
        for joint in [j for j, o in self.owner.items() if o == tag]:
            del self.owner[joint]

    # -- grasp ---------------------------------------------------------------------
    def _grasp_constraints(self, chain: Chain) -> list:
        space = self.sim.space
        body = self.character.bodies[chain.end_link]
        return [c for c in space.constraints if isinstance(c, pymunk.PivotJoint)
                and c.a is body and c.b is space.static_body]

    def _try_grasp(self, chain_name: str, points, tolerance: float) -> bool:
        if self.sim is None or chain_name in self.grasped:
            return chain_name in self.grasped
        chain = self.chains[chain_name]
        ex, ey = chain.end_world(self.character)
        for p in points:
            if math.hypot(ex - p[0], ey - p[1]) <= tolerance:
                body = self.character.bodies[chain.end_link]
                joint = pymunk.PivotJoint(body, self.sim.space.static_body, chain.end,
                                          (p[0], p[1]))
                self.sim.space.add(joint)
                self.grasped[chain_name] = [p[0], p[1]]
                return True
        return False

    def release(self, which: str) -> None:
        """Let go: remove the chain's grasp joint(s) and disarm its grasp."""
        names = list(self.chains) if which == "all" else [which]
        for name in names:
            self.grasps.pop(name, None)
            if self.grasped.pop(name, None) is not None and self.sim is not None:
                for c in self._grasp_constraints(self.chains[name]):
                    self.sim.space.remove(c)

    # -- time --------------------------------------------------------------------
    def tick(self, step: int) -> None:
        """Do the time-driven work due at ``step`` (called before stepping from it)."""
        self.now = step
        servos = self.character.servos
        seq = self.sequence
        if seq is not None:
            while seq is not None and step >= seq.until:
                pose_name = sequences.next_pose(self.plans, seq)
                if pose_name is None:
                    self._drop(SEQ)
                    self.sequence = seq = None
                else:
                    owned = {j for j, o in self.owner.items() if o == SEQ}
                    apply_pose(servos, self.poses[pose_name], owned)
            if seq is not None and SEQ not in self.owner.values():
                self.sequence = None
        if self.gesture is not None:
            self._play_gesture(step)
        for name, reach in list(self.reaches.items()) if self.reaches else ():
            tag = f"reach:{name}"
            owned = [j for j, o in self.owner.items() if o == tag]
            if not owned:
                del self.reaches[name]
                continue
            chain = self.chains[name]
            q = chain.solve(self.character, reach.point(step), servos[chain.joints[1]].target)
            for joint, angle in zip(chain.joints, q):
                if joint in owned:
                    servos[joint].target = angle
            if reach.grasp:
                self._try_grasp(name, [reach.p1], reach.tolerance)
            if step >= reach.end:
                self._drop(tag)
                del self.reaches[name]
        for name, (points, tolerance, until) in list(self.grasps.items()) if self.grasps else ():
            if self._try_grasp(name, points, tolerance) or (until is not None and step >= until):
                del self.grasps[name]
        p = self.perturber
        if p.on and p.next_kick is not None and step >= p.next_kick:
            p.kick(self.character, step)
        machine = self.machine
        if machine is not None:
            to = machine.due(step)
            for _ in range(MAX_CHAINED_GOTOS):
                if to is None:
                    break
                self._enter_state(to, step, 0)
                to = machine.due(step)
        self._reschedule(step + 1)

    def _reschedule(self, earliest: int) -> None:
        """``next_wakeup``: the first step >= ``earliest`` at which something is due,
        None when idle. Runs after every tick and key, so it is kept lean."""
        wake = None
        if self.sequence is not None:
            wake = self.sequence.until
        if self.gesture is not None:
            chord, start, index = self.gesture
            at = start + self.gestures[chord][index][0]
            wake = at if wake is None or at < wake else wake
        if self.reaches or self.grasps:
            wake = earliest
        p = self.perturber
        if p.on and p.next_kick is not None:
            wake = p.next_kick if wake is None or p.next_kick < wake else wake
        if self.machine is not None:
            at = self.machine.next_check(earliest)
            if at is not None and (wake is None or at < wake):
                wake = at
        self.next_wakeup = wake if wake is None or wake > earliest else earliest

    # -- reset and snapshots -------------------------------------------------------
    def reset(self) -> None:
        """After the character is reset: start-pose targets, then the current inputs."""
        start = self.character.start_joint_angles()
        for name, servo in self.character.servos.items():
            servo.target = start.get(name, 0.0)
        self._clear_activity()  # the restored space has no grasp joints either
        self.perturber.reset()
        self.apply_gains()
        self._start_control()
        self.apply_maps()

    # The runtime's own state rides along with physics snapshots (plain data).
    def get_state(self) -> dict:
        return {"inputs": dict(self.inputs), "held": sorted(self.held), "mode": self.mode,
                "owner": dict(self.owner),
                "sequence": self.sequence.to_state() if self.sequence else None,
                "gesture": list(self.gesture) if self.gesture else None,
                "reaches": {n: r.to_state() for n, r in self.reaches.items()},
                "grasps": _copy_grasps(self.grasps),
                "grasped": {n: list(p) for n, p in self.grasped.items()},
                "gain_holds": _copy_holds(self.gain_holds),
                "machine": self.machine.get_state() if self.machine else None,
                "perturb": self.perturber.get_state(), "next_wakeup": self.next_wakeup}

    def set_state(self, state: dict) -> None:
        self.inputs = dict(state["inputs"])
        self.held = set(state["held"])
        if "owner" not in state:  # an old-style state: inputs only
            return
        self.mode = state["mode"]
        self.owner = dict(state["owner"])
        self.sequence = sequences.RunningSequence.from_state(state["sequence"])
        self.gesture = list(state["gesture"]) if state.get("gesture") else None
        self.reaches = {n: Reach.from_state(r) for n, r in state["reaches"].items()}
        self.grasps = _copy_grasps(state["grasps"])
        self.grasped = {n: list(p) for n, p in state["grasped"].items()}
        self.gain_holds = _copy_holds(state["gain_holds"])
        if self.machine is not None and state["machine"] is not None:
            self.machine.set_state(state["machine"])
        self.perturber.set_state(state["perturb"])
        self.next_wakeup = state["next_wakeup"]
        self._refresh_active_maps()


def _copy_grasps(grasps: dict) -> dict:
    """A deep copy of armed grasps (chain -> [points, tolerance, until step])."""
    return {n: [[list(p) for p in points], tolerance, until]
            for n, (points, tolerance, until) in grasps.items()}


def _copy_holds(holds: dict) -> dict:
    """A deep copy of gain holds (chord -> joint -> [stiffness, damping])."""
    return {c: {j: list(v) for j, v in h.items()} for c, h in holds.items()}
