"""Run an interface file: input events in, PD targets and gains out.

The runtime is an arbiter over controllers (``puppet.interface.controllers``): it
holds the key bindings (``interface.bindings``: who owns a press, decided there once),
the active maps (``interface.active_maps``) and the joint owner table, runs the action
a key stands for (``interface.actions``), and asks its controllers (pose sequences,
gestures, reaches, grasps, random motion, state machines) to do their time-driven work.

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
(slowdown, gravity, friction, perturb, push), track/kinematic, mode, goto (the new
state's maps, then its ``enter`` action), stiffness/damping, pose, set, adjust,
sequence, release, grasp, reach.
"""

from __future__ import annotations

from puppet.data.actions import ActionSpec
from puppet.data.interfaces import InterfaceSpec
from puppet.data.keys import POINTER, pointer_value
from puppet.interface import maps as mapping
from puppet.interface.actions import MAX_CHAINED_GOTOS, Actions
from puppet.interface.active_maps import ActiveMaps, every_map
from puppet.interface.bindings import KeyBindings, Resolved
from puppet.interface.buffer import InputBuffer
from puppet.interface.conditions import reader
from puppet.interface.control_rate import ControlPeriod
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
from puppet.interface.events import AnalogNames, Event
from puppet.interface.ik import Chain
from puppet.interface.ownership import JointOwners
from puppet.interface.poll_plan import plan_for
from puppet.interface.roles import RoleBinding
from puppet.interface.runtime_state import RuntimeState
from puppet.physics.character import Character


class InterfaceRuntime(RuntimeState, ActiveMaps, Actions):
    """The arbiter: composes the key bindings (``interface.bindings``), the active maps
    (``interface.active_maps``) and the actions (``interface.actions``) over the
    controllers and state machines it holds; its reset, snapshots and hot reload are
    in ``interface.runtime_state``."""

    def __init__(self, spec: InterfaceSpec, character: Character, sim=None,
                 dt: float | None = None, start: bool = True):
        """``start=False``: touch no servo (no gains, no state entry); the caller then
        gives the runtime its state (``set_state`` from a snapshot, or ``adopt``)."""
        self.spec = spec
        self.character = character
        self.sim = sim
        self.dt = dt if dt is not None else (sim.dt if sim is not None else 1.0 / 480.0)
        self.now = 0  # current step when there is no Simulation to ask
        # (step, n): the kernel's loop entered n chained states at step and left the
        # rest of the chain to this step's tick (poll_states), which enters at most
        # MAX_CHAINED_GOTOS in all at a step
        self.chained: tuple[int, int] | None = None
        # Roles: names that mean one joint or link in one binding, another in the next
        # (the stance leg and the swing leg); poses and maps are resolved per binding.
        self.roles = RoleBinding(spec)
        self._use_binding(spec.start_binding)
        # a key for other scenes (``scenes:``) is not bound here
        scene = sim.scene_spec.name if sim is not None else None
        self.key_bindings = KeyBindings(spec, scene)
        machines = spec.state_machines()
        self.channels: dict[str, float] = {}  # channel.NAME inputs, by bare NAME
        self.inputs: dict[str, float] = {}  # one dict for the runtime's life (shared)
        self.machines = {name: StateMachine(name, m, spec, character, self.dt, self.channels,
                                            self.inputs)
                         for name, m in machines.items()}
        for machine in self.machines.values():
            machine.use_renamer(self.role_binding, self.roles.sensor)
        self._machine_list = tuple(self.machines.values())  # (tick)
        # the machines with a state polling device inputs alone (an input event stirs them)
        self._device_machines = tuple(m for m in self._machine_list if m.has_quiet_states)
        self.buffer = InputBuffer(self.key_bindings.state, self.dt)  # presses a state takes later
        self.chains = {n: Chain.from_spec(n, c, character.spec) for n, c in spec.chains.items()}
        self.held: set[str] = set()
        self.owners = JointOwners()
        servos = character.servos
        self.sequences = SequenceController(
            spec.sequences, self.poses, servos, self.owners, self.dt,
            lambda name: reader(self.roles.sensor(name), character, self.channels,
                                self.inputs))
        self.gestures = GestureController(spec.gestures, servos, self.owners, self.dt)
        self.gestures.inputs = self.inputs
        self.grasping = GraspController(self.chains, character, sim, self.dt)
        self.reaching = ReachController(self.chains, character, sim, self.owners, servos,
                                        self.grasping, self.read_input, self.dt)
        self.perturber = Perturber(spec.perturbation, character, self.dt)
        # the control period: the interface's control_rate, faster in a state that asks
        self.period = ControlPeriod(spec, machines, self.dt)
        every = self.period.base
        self.frames = FrameTargets(character, self.owners, every)
        self.sequences.frames = self.frames
        self.blends = BlendController(character, self.owners, self.frames, every)
        self.feedback = Feedback(servos, self.owners, self.inputs, every, character.sample,
                                 character)
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
            if tracking.reaction is not None and tracking.reaction.library is not None:
                from puppet.data.motion_library import library_named

                self.tracker.library = library_named(tracking.reaction.library.file,
                                                     character.spec.name)
            if tracking.contacts is not None:  # Ishigaki's intentional contacts: the grasps
                self.tracker.held_points = lambda: self.grasping.held
            if tracking.walk_in_place is not None:  # the example walk (Oshita 2006)
                from puppet.data.motion_library import library_named
                from puppet.interface.controllers.tracking_walk import GaitCycle

                walk = tracking.walk_in_place
                self.tracker.walk_cycle = GaitCycle(
                    library_named(walk.library, character.spec.name), walk)
        self._readers: dict[str, object] = {}  # sensor.X -> reader (file units)
        # Tick order (the state machines tick after them): what runs writes its targets,
        # then the frame targets are re-solved, then feedback maps set and add.
        self.controllers = (self.sequences, self.gestures, self.reaching, self.grasping,
                            self.perturber, self.tracker, self.blends, self.frames,
                            self.feedback)
        self._watched = tuple((c, c.BUSY, c.next_wakeup) for c in self.controllers)
        self._active: list = []  # controllers with work scheduled (next wake-up not None)
        self._controllers_wake: int | None = None  # the earliest of theirs
        self.next_wakeup: int | None = None
        self._map_cache: dict[tuple, object] = {}  # (map id, binding) -> applier
        self._channel_maps: dict[tuple, tuple] = {}  # channel names -> (names, their maps)
        self._input_maps: dict[tuple, list] = {}  # (binding, input names) -> their maps
        self._active_cache: dict[tuple, tuple] = {}  # (binding, active maps) -> compiled
        self._pending: list[list] = []  # channel frames not yet applied (see _on_channels)
        # pointer.x / pointer.y: the mouse, or the gamepad's pointer stick (only kept when
        # a map reads them)
        self._pointer = any(n in POINTER for m in every_map(spec) for n in m.inputs)
        stick = spec.gamepad.pointer
        self._stick_names = AnalogNames()  # (a gamepad event's analog input, or None)
        self._pointer_axes = {f"gamepad.{stick}_x": "pointer.x",
                              f"gamepad.{stick}_y": "pointer.y"}
        self.mode = spec.start_mode
        self.poll = plan_for(self)  # every-step polls in the kernel (Session.advance)
        self.gain_holds: dict[str, dict[str, list[float]]] = {}  # chord -> joint -> [k, d]
        if start:
            self.apply_gains()
            self._start_control()
        self.prime()

    def prime(self) -> None:
        """The states' compiled forms made now, not at each one's first entry: the
        machines' plans, the active maps of each mode and state, the poll plan's
        tables (the same objects a first entry would make: no state changes)."""
        for machine in self._machine_list:
            machine.prime()
        self.prime_maps()
        if self.poll is not None:
            self.poll.prime()

    def _use_binding(self, binding: str | None) -> None:
        """Resolve roles as ``binding`` says from now on (poses, maps, sensors)."""
        poses = self.roles.use(binding)
        self.poses = poses
        targets = self.__dict__.setdefault("_pose_targets", {})  # (per binding: a gait
        got = targets.get(binding)  # re-binds at every other state it enters)
        if got is None or got[0] is not poses:
            got = targets[binding] = (poses, {n: p.targets for n, p in poses.items()})
        self.pose_targets = got[1]
        if "sequences" in self.__dict__:
            self.sequences.poses = poses
            self.sequences.readers = {}  # ``until`` sensors named through roles
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

    # -- maps ------------------------------------------------------------------------------
    def _start_control(self) -> None:
        now = self.step_now()
        for machine in self.machines.values():
            machine.enter(machine.initial, now)
            roles = machine.spec.states[machine.initial].roles
            if roles is not None and roles != self.role_binding:
                self._use_binding(roles)  # entering a state selects its roles, the first too
        self._follow_rate()
        self._refresh_active_maps()
        for _, joints in self.feedback.setters:  # sensor maps own their joints
            self.feedback.claim(joints)
        tracking = self.spec.tracking
        if tracking is not None and tracking.start != OFF:
            self.tracker.switch(tracking.start, now, blend=False)
        for name in self.machines:
            self._run_entry(name, now, 0)
        self._reschedule(now)

    # -- input -------------------------------------------------------------------
    def _lookup(self, chord: str) -> tuple[ActionSpec | None, str | None]:
        """The action bound to a chord now and the machine it belongs to: each machine's
        current state's keys, then its any_state keys, then the top level's."""
        return self.key_bindings.lookup(chord, self.machines)

    def resolve(self, chord: str) -> Resolved:
        """Who owns ``chord`` now, the interface or the app (``interface.bindings``: the
        one place that decides it)."""
        return self.key_bindings.resolve(chord, self.machines, self.gestures.paths)

    def binding(self, chord: str) -> ActionSpec | None:
        """The action bound to a chord in the current states (state keys first)."""
        return self._lookup(chord)[0]

    def handles_key(self, chord: str) -> bool:
        return self.resolve(chord).interface

    def on_event(self, event: Event, resolved: Resolved | None = None):
        """Apply an input event at the current step. Returns an app action the event
        asks for (an ``AppAction`` or ``SetSlowdown``), for the session to perform or
        pass on. ``resolved``: a key press's owner, when the caller has resolved it
        already at this step (a press is resolved once)."""
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
                if table and written:  # (a frame map's holds: nothing to take)
                    self.owners.take(written)
            self._maps_applied()
            return None
        if kind == "gamepad":  # a stick, a trigger, an axis (the frequent case): maps only
            name = self._stick_names[event["name"]]
            if name is not None:
                value = float(event["value"])
                self.inputs[name] = value
                pointer = self._pointer and self._pointer_axes.get(name)
                if pointer:  # the pointer stick moves the pointer, as the mouse does
                    self.inputs[pointer] = pointer_value(value)
                self.apply_maps((name, pointer) if pointer else (name,))
                self._maps_applied()
                return None
        now = self.step_now()
        result = None
        if kind == "key":
            result = self._press(event["key"], event["down"], now, resolved)
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
            self.apply_maps((name,))  # (sticks, and with them the pointer, went above)
            if kind != "channel" and (was > 0.5) != (value > 0.5):
                result = self._press(name, value > 0.5, now)  # buttons also act as keys
        else:
            return None
        if self._device_machines:
            self._stir(now)
        self._reschedule(now)
        return result

    def _stir(self, now: int) -> None:
        """An input event at ``now``: a machine in a state that polls device inputs
        alone polls again at its next control step (``StateMachine.quiet``)."""
        wake = self.next_wakeup
        for machine in self._device_machines:
            if machine.device_only:
                machine.quiet = False
                at = machine.next_wakeup(now)
                if at is not None and (wake is None or at < wake):
                    wake = at
        self.next_wakeup = wake

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
            moved = self.tracker.sampled(self.step_now())
            if self.tracker.due:  # found: the stream is back
                self._tracking_due(self.step_now())
            if moved:  # between two control steps: the tracker acts on it at once
                self._reschedule(self.step_now())
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

    def _maps_applied(self) -> None:
        """After a mouse or stick event's maps: a map holding a frame target has it
        re-solved, and a state polling the device polls it again. Nothing else that
        sets a wake-up changes (an emptied sequence or gesture ends at its own next
        wake-up), so there is no reschedule."""
        if self.frames.held and self.frames not in self._active:
            self._reschedule(self.step_now())
        if self._device_machines:
            self._stir(self.step_now())

    # -- time --------------------------------------------------------------------
    def tick(self, step: int) -> None:
        """Do the time-driven work due at ``step`` (called before stepping from it)."""
        self.now = step
        if self._pending:
            self.flush()
        chained, self.chained = self.chained, None
        active = self._active
        waited = True  # every controller only waited (see controllers.base.WAITED)
        for controller in active:
            if controller.tick(step) is not WAITED:
                waited = False
        if self.tracker.due:  # lost, or a fall: the interface's balance, its get-up
            self._tracking_due(step)
            waited = False  # (a goto, a blend: the controllers' wake-ups are stale)
        moved = False
        for machine in self._machine_list:
            to = machine.due(step)
            if to is not None:
                budget = MAX_CHAINED_GOTOS
                if chained is not None and chained[0] == step:
                    budget -= chained[1]
                for _ in range(budget):
                    self._enter_state(to[0], to[1], step, 0)
                    moved = True
                    to = machine.due(step)
                    if to is None:
                        break
        if moved or not waited or (self.frames.held and self.frames not in active):
            self._reschedule(step + 1, not moved)  # (a sensor map held a frame target)
        else:  # every controller idle or waiting, and no state entered: the controllers'
            earliest = step + 1  # wake-ups stand, only the machines' move on
            wake = self._controllers_wake
            for machine in self._machine_list:
                at = machine.wake_after  # next_wakeup(earliest), worked out by due
                if at is not None and (wake is None or at < wake):
                    wake = at
            self.next_wakeup = wake if wake is None or wake > earliest else earliest

    def _follow_rate(self) -> None:
        """The control period the current states ask for (``interface.control_rate``),
        on everything that keeps one: the machines, frame targets, blends, sensor maps.
        Runs after a state is entered or restored; free without state rates."""
        period = self.period
        if not period.fast:
            return
        every = period.now(self.machines)
        if every != period.every:
            period.every = every
            for machine in self._machine_list:
                machine.every = every
            self.frames.every = self.blends.every = self.feedback.every = every

    def _reschedule(self, earliest: int, machines_due: bool = False) -> None:
        """``next_wakeup``: the first step >= ``earliest`` at which something is due,
        None when idle; and which controllers have work. Runs after every tick and key,
        so it is kept lean (``machines_due``: every machine's ``wake_after`` is its
        ``next_wakeup(earliest)``, a tick's ``due`` having worked it out)."""
        wake = None
        active = []
        for controller, busy, next_wakeup in self._watched:
            if getattr(controller, busy):  # idle controllers are not asked (hot path)
                at = next_wakeup(earliest)
                if at is not None:
                    active.append(controller)
                    if wake is None or at < wake:
                        wake = at
        self._controllers_wake = wake
        if machines_due:
            for machine in self._machine_list:
                at = machine.wake_after
                if at is not None and (wake is None or at < wake):
                    wake = at
        else:
            for machine in self._machine_list:
                at = machine.next_wakeup(earliest)
                if at is not None and (wake is None or at < wake):
                    wake = at
        self._active = active
        self.next_wakeup = wake if wake is None or wake > earliest else earliest
