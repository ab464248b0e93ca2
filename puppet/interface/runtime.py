"""Run an interface file: input events in, PD targets and gains out.

The runtime is an arbiter over controllers (``puppet.interface.controllers``): it
holds the bindings, the continuous maps and the joint owner table, runs the action a
key stands for, and asks its controllers (pose sequences, gestures, reaches, grasps,
random motion, state machines) to do their time-driven work.

It is event driven: targets change when an input changes, so between events the
physics steps at full speed with nothing to do in Python. Time-driven work announces
itself through ``next_wakeup``, the minimum over the controllers of the sim step at
which ``tick`` must next run; ``None`` means idle, and the session then steps the
physics in one tight loop.

Arbitration - who writes a joint's target - follows "the most recent action wins",
per joint (``puppet.interface.ownership``):
  * a running sequence, gesture or reach *owns* the joints it drives;
  * a new sequence replaces the running sequence entirely; a new reach replaces the
    running reach of the same chain; either takes its joints from the other;
  * a pose, set or adjust (key, or state entry) and a continuous map that updates
    (its input changed, or its mode/state became active) take the joints they write
    back from any sequence or reach, which carries on with its remaining joints and
    ends when it has none;
  * gains (stiffness/damping) are not owned: the latest write wins.
An action's parts run in this order, later ones winning on shared joints: app/meta
(slowdown, gravity, friction, perturb, push), track/kinematic, mode, goto (the new state's maps, then its
``enter`` action), stiffness/damping, pose, set, adjust, sequence, release, grasp,
reach.
"""

from __future__ import annotations

import math

from puppet.data.actions import ActionSpec
from puppet.data.interfaces import InterfaceSpec
from puppet.data.keys import POINTER, normalize_key, pointer_value
from puppet.interface import maps as mapping
from puppet.interface import meta
from puppet.interface.app_keys import AppAction, SetSlowdown
from puppet.interface.buffer import InputBuffer
from puppet.interface.conditions import map_reader
from puppet.interface.controllers.base import WAITED
from puppet.interface.controllers.blend import BlendController
from puppet.interface.controllers.feedback import Feedback
from puppet.interface.controllers.frame import FrameTargets
from puppet.interface.controllers.gesture import GestureController
from puppet.interface.controllers.grasp import GraspController
from puppet.interface.controllers.perturbation import Perturber
from puppet.interface.controllers.reach import ReachController
from puppet.interface.controllers.sequence import SequenceController
from puppet.interface.controllers.state_machine import StateMachine
from puppet.interface.controllers.tracking import OFF, Tracker
from puppet.interface.events import Event, is_analog
from puppet.interface.ik import Chain
from puppet.interface.ownership import FEEDBACK, FRAME, JointOwners
from puppet.interface.poses import apply_pose, frame_target
from puppet.interface.roles import RoleBinding
from puppet.physics.character import Character

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
        # Roles: names that mean one joint or link in one binding, another in the next
        # (the stance leg and the swing leg); poses and maps are resolved per binding.
        self.roles = RoleBinding(spec)
        self._use_binding(spec.start_binding)
        # a key for other scenes (``scenes:``) is not bound here
        scene = sim.scene_spec.name if sim is not None else None
        self.bindings = {normalize_key(k.key): k for k in spec.keys if k.plays_on(scene)}
        machines = spec.state_machines()
        self.channels: dict[str, float] = {}  # channel.NAME inputs, by bare NAME
        self.inputs: dict[str, float] = {}  # one dict for the runtime's life (shared)
        self.machines = {name: StateMachine(name, m, spec, character, self.dt, self.channels,
                                            self.inputs)
                         for name, m in machines.items()}
        for machine in self.machines.values():
            machine.use_renamer(self.role_binding, self.roles.sensor)
        self._machine_list = tuple(self.machines.values())  # (tick)
        # (machine, state) -> chord -> action; machine -> chord -> action (any_state)
        self.state_bindings = {(mname, sname): {normalize_key(k.key): k for k in s.keys
                                                if k.plays_on(scene)}
                               for mname, m in machines.items()
                               for sname, s in m.states.items()}
        self.any_bindings = {mname: {normalize_key(k.key): k for k in m.any_state.keys
                                     if k.plays_on(scene)}
                             for mname, m in machines.items()}
        self.buffer = InputBuffer(self.state_bindings, self.dt)  # presses a state takes later
        self.chains = {n: Chain.from_spec(n, c, character.spec) for n, c in spec.chains.items()}
        self.held: set[str] = set()
        self.owners = JointOwners()
        servos = character.servos
        self.sequences = SequenceController(spec.sequences, self.poses, servos, self.owners,
                                            self.dt)
        self.gestures = GestureController(spec.gestures, servos, self.owners, self.dt)
        self.gestures.inputs = self.inputs
        self.grasping = GraspController(self.chains, character, sim, self.dt)
        self.reaching = ReachController(self.chains, character, sim, self.owners, servos,
                                        self.grasping, self.read_input, self.dt)
        self.perturber = Perturber(spec.perturbation, character, self.dt)
        every = max(1, round(1.0 / (spec.control_rate * self.dt)))  # the control period
        self.frames = FrameTargets(character, self.owners, every)
        self.sequences.frames = self.frames
        self.blends = BlendController(character, self.owners, self.frames, every)
        self.feedback = Feedback(servos, self.owners, self.inputs, every, character.sample)
        self.tracker = Tracker(spec.tracking, character, self.owners, self.channels, every,
                               self.dt, self.restore_gains,
                               None if sim is None else sim.ground_surface)
        tracking = spec.tracking
        if tracking is not None:  # the poses tracking stands the figure in, as its channels
            joints = self.tracker.joints
            used = [tracking.stand] if tracking.stand is not None else []
            if tracking.reaction is not None and tracking.reaction.get_up is not None:
                used += [step.pose for step in tracking.reaction.get_up.steps]
            self.tracker.poses = {name: {joints[j]: v for j, v in
                                         spec.poses[name].joint_degrees().items()
                                         if j in joints} for name in used}
            if tracking.stand is not None:
                self.tracker.stand = self.tracker.poses[tracking.stand]
        self._readers: dict[str, object] = {}  # sensor.X -> reader (file units)
        # Tick order (the state machines tick after them): what runs writes its targets,
        # then the frame targets are re-solved, then feedback maps set and add.
        self.controllers = (self.sequences, self.gestures, self.reaching, self.grasping,
                            self.perturber, self.tracker, self.blends, self.frames,
                            self.feedback)
        self._watched = [(c, c.BUSY) for c in self.controllers]
        self._active: list = []  # controllers with work scheduled (next wake-up not None)
        self._controllers_wake: int | None = None  # the earliest of theirs
        self.next_wakeup: int | None = None
        self._map_cache: dict[tuple, object] = {}  # (map id, binding) -> applier
        self._channel_maps: dict[tuple, tuple] = {}  # channel names -> (names, their maps)
        self._active_cache: dict[tuple, tuple] = {}  # (binding, active maps) -> compiled
        self._pending: list[list] = []  # channel frames not yet applied (see _on_channels)
        # pointer.x / pointer.y: the mouse, or the gamepad's pointer stick (only kept when
        # a map reads them)
        self._pointer = any(n in POINTER for m in _every_map(spec) for n in m.inputs)
        stick = spec.gamepad.pointer
        self._pointer_axes = {f"gamepad.{stick}_x": "pointer.x",
                              f"gamepad.{stick}_y": "pointer.y"}
        self.mode = spec.start_mode
        self.gain_holds: dict[str, dict[str, list[float]]] = {}  # chord -> joint -> [k, d]
        if start:
            self.apply_gains()
            self._start_control()

    def _use_binding(self, binding: str | None) -> None:
        """Resolve roles as ``binding`` says from now on (poses, maps, sensors)."""
        poses = self.roles.use(binding)
        self.poses = poses
        self.pose_targets = {n: p.targets for n, p in poses.items()}
        if "sequences" in self.__dict__:
            self.sequences.poses = poses
        for machine in self.__dict__.get("machines", {}).values():
            machine.use_renamer(binding, self.roles.sensor)

    @property
    def role_binding(self) -> str | None:
        return self.roles.binding

    # -- what runs (read by the HUD, replays and tests) -------------------------------
    @property
    def state(self) -> str | None:
        """The first state machine's current state (None without states)."""
        for machine in self.machines.values():
            return machine.current
        return None

    @property
    def states(self) -> dict[str, str]:
        """machine -> its current state."""
        return {name: m.current for name, m in self.machines.items()}

    @property
    def machine(self) -> StateMachine | None:
        return next(iter(self.machines.values()), None)

    @property
    def sequence(self):
        return self.sequences.running

    @property
    def gesture(self):
        return self.gestures.running

    @property
    def reaches(self):
        return self.reaching.reaches

    @property
    def grasped(self) -> dict[str, tuple[float, float]]:
        return self.grasping.held

    def step_now(self) -> int:
        return self.sim.steps if self.sim is not None else self.now

    def read_input(self, name: str, default: float | None = None) -> float | None:
        """An input's value now (mouse.x, gamepad.left_x, channel.NAME...)."""
        if name.startswith("channel."):
            return self.channels.get(name[8:], default)
        return self.inputs.get(name, default)

    def input_names(self) -> list[str]:
        """Every input that has a value."""
        return list(self.inputs) + ["channel." + n for n in self.channels]

    # -- hot reload ----------------------------------------------------------------------
    def adopt(self, old: InterfaceRuntime) -> None:
        """Take over from ``old``, the runtime of the interface this one replaces (a hot
        reload): the physics and the servo targets stay as they are, so nothing moves
        until an input changes or a key is pressed; input values and held keys carry
        over; so does what is running (sequence, gesture, reaches, grasps, gain holds,
        states, mode, random motion) where the new interface defines it the same way.
        The rest ends, leaving its joints' targets where they are."""
        now = old.step_now()
        self.now = old.now
        self.inputs.update(old.inputs)
        self.channels.update(old.channels)
        for _, values in old._pending:  # stored, as old's flush would (its maps are gone)
            self.channels.update(values)
        self.held = set(old.held)
        self.buffer.set_state(old.buffer.get_state())
        spec, was = self.spec, old.spec
        self.mode = old.mode if old.mode in spec.modes else spec.start_mode
        if old.role_binding in spec.bindings:
            self._use_binding(old.role_binding)

        def same(kind: str, name: str) -> bool:
            if kind == "sequence":
                return (name in spec.sequences and spec.sequences[name] == was.sequences.get(name)
                        and all(spec.poses.get(p.pose) == was.poses.get(p.pose)
                                for p in spec.sequences[name]))
            if kind == "chain":
                return name in spec.chains and spec.chains[name] == was.chains.get(name)
            if kind == "tracking":
                return spec.tracking == was.tracking
            return spec.perturbation == was.perturbation

        kept = set()
        for mine, theirs in zip(self.controllers, old.controllers):
            kept |= mine.adopt(theirs, same, now)
        self.owners.table = dict(old.owners.table)
        self.owners.keep_only(kept)
        if spec.gains == was.gains:
            self.gain_holds = _copy_holds(old.gain_holds)
        else:
            self.apply_gains()
            if self.tracker.scaled:  # still tracking under KD: its gains again
                self.tracker.scale_gains(list(self.tracker.scaled))
        fresh = []
        for name, machine in self.machines.items():
            theirs = old.machines.get(name)
            if theirs is not None and theirs.current in machine.spec.states:
                machine.set_state(theirs.get_state())
            else:  # a new state machine (or its state is gone): start it
                machine.enter(machine.initial, now)
                fresh.append(name)
        self._refresh_active_maps()
        for name in fresh:
            self._run_entry(name, now, 0)
        self._reschedule(now)

    # -- maps ------------------------------------------------------------------------------
    def _start_control(self) -> None:
        now = self.step_now()
        for machine in self.machines.values():
            machine.enter(machine.initial, now)
            roles = machine.spec.states[machine.initial].roles
            if roles is not None and roles != self.role_binding:
                self._use_binding(roles)  # entering a state selects its roles, the first too
        self._refresh_active_maps()
        for applier, joints in self.feedback.setters:  # sensor maps own their joints
            self.feedback.claim(joints)
        tracking = self.spec.tracking
        if tracking is not None and tracking.start != OFF:
            self.tracker.switch(tracking.start, now, blend=False)
        for name in self.machines:
            self._run_entry(name, now, 0)
        self._reschedule(now)

    def _refresh_active_maps(self) -> None:
        if self._pending:
            self.flush()  # with the maps that were active when their events came
        spec = self.spec
        active = list(spec.maps)
        if self.mode is not None:
            active += spec.modes[self.mode]
        for machine in self.machines.values():
            active += machine.spec.states[machine.current].maps
        self.active_maps = active
        # What a set of active maps compiles to, under a binding, is worked out once (a
        # gait enters a state every step): the appliers are plain functions of the inputs
        key = (self.role_binding, tuple(map(id, active)))
        compiled = self._active_cache.get(key)
        if compiled is None:
            joints: set[str] = set()
            for m in active:
                if any(n in ("mouse.x", "mouse.y") + POINTER for n in m.inputs):
                    joints |= self._map_joints(m)
            compiled = self._active_cache[key] = (
                mapping.fused(self._compiled(("mouse.x", "mouse.y") + POINTER)),
                self._feedback_maps(active), frozenset(joints), {})
        self._mouse_maps, (readers, setters, adders), joints, self._channel_maps = compiled
        self.feedback.set_maps(list(readers), list(setters), list(adders))
        self.gestures.mouse_maps = self._mouse_maps  # what a gesture plays through
        self.gestures.mouse_joints = set(joints)

    def _compiled(self, inputs) -> list:
        """Compiled appliers of the active device maps reading any of ``inputs``, in
        order (feedback maps run at the control rate instead)."""
        return [self._applier(m) for m in self.active_maps
                if not m.feedback and any(i in inputs for i in m.inputs)]

    def _feedback_maps(self, active) -> tuple:
        """The active feedback maps (sensor inputs, ``add``) as their controller takes
        them: (readers, setters, adders)."""
        readers, setters, adders = {}, [], []
        for m in active:
            if not m.feedback:
                continue
            for name in self.roles.map(m).inputs:
                if name.startswith("sensor.") and name not in readers:
                    read = self._readers.get(name)
                    if read is None:
                        read = self._readers[name] = map_reader(name[7:], self.character)
                    readers[name] = read
            if getattr(m, "combine", "set") == "add":
                adders.append(self._applier(m))
            else:
                setters.append((self._applier(m), tuple(sorted(self._map_joints(m)))))
        return tuple(readers.items()), tuple(setters), tuple(adders)

    def _map_joints(self, m) -> set[str]:
        m = self.roles.map(m)
        if getattr(m, "grid", None) is not None:
            these = {j for row in m.grid for p in row for j in self.pose_targets[p]}
            return these if m.joints is None else these & set(m.joints)
        return set(m.gains())

    def _applier(self, m):
        """The compiled form of map ``m`` (compiled once per runtime)."""
        key = (id(m), self.role_binding)
        applier = self._map_cache.get(key)
        if applier is None:
            m = self.roles.map(m)
            if getattr(m, "combine", "set") == "add":
                applier = mapping.compile_contribution(m, self.channels)
            else:
                applier = mapping.compile_map(m, self.character.servos, self.pose_targets,
                                              self.channels, self.frames,
                                              FEEDBACK if m.feedback else None)
            self._map_cache[key] = applier
        return applier

    def pointer_for_pose(self, tolerance_deg: float = 2.0) -> tuple[float, float] | None:
        """The mouse position (x, y in 0..1) at which the active mouse maps give the
        targets the joints have now (at the start: the start pose), or None if no
        position comes within ``tolerance_deg`` on every joint they drive. The window
        puts the pointer there when it opens, so its first mouse event does not snap
        the character out of its pose (the middle of luxo-mouse throws Luxo over).
        A grid search, then a pattern search; the targets are left as they were."""
        if self._pending:
            self.flush()
        mouse_joints = self.gestures.mouse_joints
        if not self._mouse_maps or not mouse_joints:
            return None
        servos = self.character.servos
        want = {j: servos[j].target for j in mouse_joints}
        values = dict(self.inputs)

        def score(x: float, y: float) -> tuple[float, float]:
            values["mouse.x"], values["mouse.y"] = x, y
            values["pointer.x"], values["pointer.y"] = x, y
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

    def apply_maps(self, inputs=None) -> None:
        """Re-evaluate the active maps that read ``inputs`` (default: all inputs)."""
        inputs = self.input_names() if inputs is None else inputs
        for apply in self._compiled(set(inputs)):
            self.owners.take(apply(self.inputs))

    def _activate(self, maps) -> None:
        """Maps that just became active (a mode or state entered) act at once with the
        inputs as they are; the maps that were active already leave their joints be. A
        sensor map takes its joints, and writes them at the next control step."""
        for m in maps:
            if not m.feedback:
                self.owners.take(self._applier(m)(self.inputs))
            elif getattr(m, "combine", "set") != "add":
                self.feedback.claim(self._map_joints(m))

    # -- input -------------------------------------------------------------------
    def _lookup(self, chord: str) -> tuple[ActionSpec | None, str | None]:
        """The action bound to a chord now and the machine it belongs to: each machine's
        current state's keys, then its any_state keys, then the top level's."""
        for name, machine in self.machines.items():
            found = self.state_bindings[(name, machine.current)].get(chord)
            if found is None:
                found = self.any_bindings[name].get(chord)
            if found is not None:
                return found, name
        return self.bindings.get(chord), None

    def binding(self, chord: str) -> ActionSpec | None:
        """The action bound to a chord in the current states (state keys first)."""
        return self._lookup(chord)[0]

    def handles_key(self, chord: str) -> bool:
        return self.binding(chord) is not None or chord in self.gestures.paths

    def on_event(self, event: Event):
        """Apply an input event at the current step. Returns an app action the event
        asks for (an ``AppAction`` or ``SetSlowdown``), for the session to perform or
        pass on."""
        kind = event["type"]
        if kind == "channels":
            self._on_channels(event["values"])
            return None
        if self._pending:
            self.flush()
        if kind == "mouse":
            self.inputs["mouse.x"] = event["x"]
            self.inputs["mouse.y"] = event["y"]
            if self._pointer:
                self.inputs["pointer.x"], self.inputs["pointer.y"] = event["x"], event["y"]
            values, table = self.inputs, self.owners.table
            for apply in self._mouse_maps:  # the hot path: no lookups, no allocation
                written = apply(values)
                if table:
                    self.owners.take(written)
            if self.frames.held and self.frames not in self._active:
                self._reschedule(self.step_now())  # a map holds a frame target: re-solve it
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
            was = self.read_input(name, 0.0)
            if kind == "channel":
                self.channels[event["name"]] = value
                if self.tracker.mode != OFF:
                    self.tracker.sampled(now)
                    if self.tracker.due:
                        self._tracking_due(now)
            else:
                self.inputs[name] = value
            pointer = self._pointer and self._pointer_axes.get(name)
            if pointer:  # the pointer stick moves the pointer, as the mouse does
                self.inputs[pointer] = pointer_value(value)
            self.apply_maps((name, pointer) if pointer else (name,))
            if kind != "channel" and not is_analog(name) \
                    and (was > 0.5) != (value > 0.5):  # buttons also act as keys
                result = self._press(name, value > 0.5, now)
        else:
            return None
        self._reschedule(now)
        return result

    def _on_channels(self, values: dict[str, float]) -> None:
        """Many named channels at one step (a mocap frame): like the mouse, a compiled
        path per set of names (their input names and the maps reading any of them).
        The values and the maps are kept until anything next happens (another event, a
        tick, a step: ``flush``), which stores the values and then runs the maps, so
        that of several frames arriving at one step - a 120 Hz stream drained once per
        60 Hz frame - only the last is written to the servos (the same targets, and the
        same bits, at a fraction of the cost); a frame of the same channels as the one
        before it replaces it (its values stand for both)."""
        names = tuple(values)
        entry = self._channel_maps.get(names)
        if entry is None:  # (these names, the appliers of the maps reading any of them)
            entry = self._channel_maps[names] = (names, tuple(mapping.fused(
                self._compiled(tuple("channel." + n for n in names)))))
        if self.tracker.mode != OFF:
            if self.tracker.lost:  # the stream is back: the tracker takes its joints
                self.channels.update(values)  # by these values (stored again at flush)
            self.tracker.sampled(self.step_now())
            if self.tracker.due:  # found: the stream is back
                self._tracking_due(self.step_now())
        pending = self._pending
        if pending and pending[-1][0] is entry:
            pending[-1][1] = values
        else:
            pending.append([entry, values])

    def flush(self) -> None:
        """Store the pending channel values, then run their maps in the order their
        events came."""
        pending, self._pending = self._pending, []
        channels = self.channels
        for _, values in pending:
            channels.update(values)
        store, table = self.inputs, self.owners.table
        for entry, _ in pending:
            for apply in entry[1]:
                written = apply(store)
                if table:
                    self.owners.take(written)
        if self.frames.held and self.frames not in self._active:
            self._reschedule(self.step_now())  # a map holds a frame target: re-solve it

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

    def _press(self, chord: str, down: bool, now: int):
        if not down:
            self.held.discard(chord)
            restore = self.gain_holds.pop(chord, None)
            if restore:
                servos = self.character.servos
                for joint, (k, d) in restore.items():
                    servos[joint].stiffness, servos[joint].damping = k, d
            return None
        self.held.add(chord)
        binding, machine = self._lookup(chord)
        if binding is None:
            if chord in self.gestures.paths:
                self.gestures.start(chord, now)
            else:
                self.buffer.keep(chord, now)
            return None
        self.buffer.spend(chord)
        return self.run_action(binding, now, chord, machine=machine)

    # -- actions -----------------------------------------------------------------
    def run_action(self, a: ActionSpec, now: int, chord: str | None = None,
                   depth: int = 0, machine: str | None = None):
        """Run one action (a key's, a state's entry). ``machine``: the state machine the
        action belongs to (its ``goto`` names that machine's states first)."""
        if self._pending:
            self.flush()  # a stream's samples came first: they act first
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
            apply_pose(servos, pose, frames=frames, owner=FRAME)
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
        roles = self.machines[machine].spec.states[state].roles
        rebound = roles is not None and roles != self.role_binding
        if rebound:
            self._use_binding(roles)
        self._refresh_active_maps()
        if rebound:  # a device map on a role now means another joint: it acts there
            self._activate([m for m in self.active_maps if not m.feedback
                            and self.roles.names_role(m)])
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

    # -- time --------------------------------------------------------------------
    def tick(self, step: int) -> None:
        """Do the time-driven work due at ``step`` (called before stepping from it)."""
        self.now = step
        if self._pending:
            self.flush()
        active = self._active
        waited = True  # every controller only waited (see controllers.base.WAITED)
        for controller in active:
            if controller.tick(step) is not WAITED:
                waited = False
        if self.tracker.due:  # lost, or a fall: the interface's balance, its get-up
            self._tracking_due(step)
        moved = False
        for machine in self._machine_list:
            to = machine.due(step)
            if to is not None:
                for _ in range(MAX_CHAINED_GOTOS):
                    self._enter_state(to[0], to[1], step, 0)
                    moved = True
                    to = machine.due(step)
                    if to is None:
                        break
        if moved or not waited:
            self._reschedule(step + 1)
        else:  # every controller idle or waiting, and no state entered: the controllers'
            earliest = step + 1  # wake-ups stand, only the machines' move on
            wake = self._controllers_wake
            for machine in self._machine_list:
                at = machine.wake_after  # next_wakeup(earliest), worked out by due
                if at is not None and (wake is None or at < wake):
                    wake = at
            self.next_wakeup = wake if wake is None or wake > earliest else earliest

    def _reschedule(self, earliest: int) -> None:
        """``next_wakeup``: the first step >= ``earliest`` at which something is due,
        None when idle; and which controllers have work. Runs after every tick and key,
        so it is kept lean."""
        wake = None
        active = []
        for controller, busy in self._watched:
            if getattr(controller, busy):  # idle controllers are not asked (hot path)
                at = controller.next_wakeup(earliest)
                if at is not None:
                    active.append(controller)
                    wake = at if wake is None or at < wake else wake
        self._controllers_wake = wake
        for machine in self.machines.values():
            at = machine.next_wakeup(earliest)
            if at is not None and (wake is None or at < wake):
                wake = at
        self._active = active
        self.next_wakeup = wake if wake is None or wake > earliest else earliest

    # -- reset and snapshots -------------------------------------------------------
    def reset(self) -> None:
        """After the character is reset: start-pose targets, then the current inputs."""
        start = self.character.start_joint_angles()
        for name, servo in self.character.servos.items():
            servo.target = start.get(name, 0.0)
        for controller in self.controllers:  # the restored space has no grasp joints either
            controller.stop()
        self.owners.table = {}
        self.gain_holds = {}
        self.buffer.set_state(None)
        self.mode = self.spec.start_mode
        self._use_binding(self.spec.start_binding)
        self.apply_gains()
        self._start_control()
        self.apply_maps()

    # The runtime's own state rides along with physics snapshots (plain data).
    def get_state(self) -> dict:
        if self._pending:
            self.flush()
        return {"inputs": dict(self.inputs), "channels": dict(self.channels),
                "held": sorted(self.held), "mode": self.mode,
                "owners": self.owners.get_state(),
                "controllers": [c.get_state() for c in self.controllers],
                "machines": {n: m.get_state() for n, m in self.machines.items()},
                "gain_holds": _copy_holds(self.gain_holds), "binding": self.role_binding,
                "next_wakeup": self.next_wakeup, "buffer": self.buffer.get_state()}

    def set_state(self, state: dict) -> None:
        self.inputs.clear()
        self.inputs.update(state["inputs"])
        self.channels.clear()
        self.channels.update(state["channels"])
        self.held = set(state["held"])
        self.mode = state["mode"]
        self.owners.set_state(state["owners"])
        for controller, s in zip(self.controllers, state["controllers"]):
            controller.set_state(s)
        for name, s in state["machines"].items():
            if name in self.machines:
                self.machines[name].set_state(s)
        self.gain_holds = _copy_holds(state["gain_holds"])
        self.buffer.set_state(state.get("buffer"))
        if state["binding"] != self.role_binding:
            self._use_binding(state["binding"])
        self._pending = []
        self._refresh_active_maps()
        self._reschedule(self.step_now())
        self.next_wakeup = state["next_wakeup"]


def _copy_holds(holds: dict) -> dict:
    """A deep copy of gain holds (chord -> joint -> [stiffness, damping])."""
    return {c: {j: list(v) for j, v in h.items()} for c, h in holds.items()}


def _every_map(spec: InterfaceSpec):
    """Every map of an interface: the top level's, each mode's, each state's."""
    from puppet.data.interface_refs import all_maps

    return (m for _, m in all_maps(spec))
