"""Interface files (``interfaces/*.yaml``): how input drives a character.

The vocabulary follows the paper's action semantics: continuous maps from devices
to joint targets (linear with a response curve, coupled joints, pose grids), named
poses and pose sequences, key actions, control modes, a state machine whose states
have their own keys and maps, IK reach and grasp, meta actions (slowdown, gravity,
friction...) and rebindable app keys. The actions themselves are in
``puppet.data.actions``; cross-references (joint, pose, state names) are checked in
``puppet.data.interface_refs``.
"""

from __future__ import annotations

from typing import Annotated, Literal

from puppet.data.actions import (
    ActionSpec,
    ChainSpec,
    ConditionSpec,
    KeyActionSpec,
    PerturbSpec,
    PoseSpec,
    SequenceStepSpec,
    check_inputs,
)
from puppet.data.bounds import (  # noqa: F401 (re-exported)
    CHECKPOINT_EVERY,
    CHECKPOINT_MAX,
    CHECKPOINT_MIN,
    MAX_SLOWDOWN,
    MIN_SLOWDOWN,
)
from puppet.data.characters import CharacterSpec
from puppet.data.errors import DataError
from puppet.data.keys import APP_KEYS, key_problem, normalize_key
from puppet.data.ranges import Angle, AngleChange, Damping, Num, Stiffness, Torque
from puppet.data.tracking import TrackingSpec
from puppet.data.validate import Meta, Spec, at, dispatch, field, validate
from puppet.data.yamlfile import Located, load_file

__all__ = ["InterfaceSpec", "LinearMapSpec", "GridMapSpec",
           "KeyActionSpec", "StateSpec", "GestureSpec", "load_interface", "parse_interface",
           "check_against_character", "with_gesture"]


GESTURE_SECONDS = 600.0  # the longest gesture


class GainSpec(Spec, kw_only=True):
    stiffness: Stiffness | None = None
    damping: Damping | None = None
    max_torque: Torque | None = None


class PowerCurve(Spec, kw_only=True):
    power: Num("power")


Curve = Literal["linear", "smoothstep"] | PowerCurve


class MapSpec:
    """A map: a ``LinearMapSpec`` or a ``GridMapSpec`` (one with ``grid``). Annotated
    with this class, a field holds the one ``_map_kind`` picks (see ``dispatch``)."""

    __slots__ = ()


class LinearMapSpec(Spec, MapSpec, kw_only=True):
    """u = (input - from[0]) / (from[1] - from[0]), clamped to 0..1 (clamp), shaped by
    ``curve``; value = to[0] + u * (to[1] - to[0]) degrees; each joint's target is
    gain * value (``joint`` is ``joints: {joint: 1}``)."""

    # mouse.x (0 left .. 1 right), mouse.y (0 bottom .. 1 top), mouse.left, gamepad.axisN,
    # channel.NAME ...
    input: str | None = None
    joint: str | None = None
    # coupling: joint -> gain (sign = mirror)
    joints: dict[str, Num("coupling")] = field(default_factory=dict)
    from_: tuple[Num("input"), Num("input")] = field(name="from", default=(0.0, 1.0))
    to: tuple[AngleChange, AngleChange] | None = None  # degrees at from[0] and from[1]
    # a constant offset, degrees, added to the joints' targets while the map is active (its
    # mode or state): no input, no 'to'
    add: AngleChange | None = None
    clamp: bool = True
    curve: Curve = "linear"
    # joint: the value is the joint's angle; world: the angle of the joint's child link in the
    # world; a link's name: relative to that link
    frame: str = "joint"
    hold: Literal["child", "parent"] = "child"  # with a frame: the link whose angle the value is
    # set: the map writes the target; add: its value is added to the target whatever else writes (at
    # the control rate)
    combine: Literal["set", "add"] = "set"
    description: str = ""  # what it does, in the player's words

    def __post_init__(self):
        if self.add is not None:
            if self.input is not None or self.to is not None:
                raise ValueError("an 'add' map adds a constant (degrees) while it is "
                                 "active; it has no 'input' or 'to' (for an input's value "
                                 "added, write 'combine: add')")
            if self.frame != "joint" or self.curve != "linear":
                raise ValueError("an 'add' map adds degrees of the joint: no 'frame' or "
                                 "'curve'")
            self.combine = "add"
        elif self.input is None or self.to is None:
            raise ValueError("a map needs 'input' and 'to' (the input's values as degrees), "
                             "or 'add' (a constant, degrees, added while it is active)")
        else:
            check_inputs(self, "input")
        if self.from_[0] == self.from_[1]:
            raise ValueError("'from' must be two different input values")
        if (self.joint is None) == (not self.joints):
            raise ValueError("a map needs exactly one of 'joint' (one joint) or 'joints' "
                             "(joint -> gain)")
        if self.combine == "add" and self.frame != "joint":
            raise ValueError("an 'add' map adds degrees of the joint to its target; "
                             "'frame' goes with 'set' maps")
        if self.hold == "parent" and self.frame == "joint":
            raise ValueError("'hold: parent' says which link a 'frame' angle is for; "
                             "without 'frame' the value is the joint's own angle (add "
                             "frame: world or a link's name, or drop 'hold')")

    @property
    def feedback(self) -> bool:
        """Evaluated at the control rate (it reads sensors, or adds to a target)."""
        return self.combine == "add" or self.input.startswith("sensor.")

    def gains(self) -> dict[str, float]:
        return {self.joint: 1.0} if self.joint is not None else dict(self.joints)

    @property
    def inputs(self) -> tuple[str, ...]:
        return () if self.input is None else (self.input,)


class GridMapSpec(Spec, MapSpec, kw_only=True):
    """Bilinear interpolation over a grid of named poses (the paper's cat trot).

    ``grid`` rows go top (y = 1) to bottom (y = 0), columns left (x = 0) to right
    (x = 1); the pose targets of the four nearest poses are blended."""

    grid: Annotated[list[list[str]], Meta(min_length=1)]
    x: str = "mouse.x"
    y: str = "mouse.y"
    # drive only these of the poses' joints (default: all); with several maps over one grid, each
    # limb can have its own map
    joints: list[str] | None = None
    description: str = ""  # what it does, in the player's words
    # flip these inputs (u -> 1 - u) before the lookup: [x, y] reflects the input through the grid's
    # centre, half a cycle out of phase for a circling mouse
    mirror: list[Literal["x", "y"]] = field(default_factory=list)

    def __post_init__(self):
        check_inputs(self, "x", "y")
        widths = {len(row) for row in self.grid}
        if len(widths) != 1 or 0 in widths:
            raise ValueError("grid rows must all have the same, non-zero number of poses")
        if len(self.grid) < 2 and widths == {1}:
            raise ValueError("a grid needs at least two poses")
        if len(set(self.mirror)) != len(self.mirror):
            raise ValueError(f"'mirror' names an axis twice: {self.mirror}")
        if self.joints is not None:
            if not self.joints:
                raise ValueError("'joints' is empty; leave it out to drive all the "
                                 "poses' joints")
            if len(set(self.joints)) != len(self.joints):
                raise ValueError(f"'joints' names a joint twice: {self.joints}")

    @property
    def inputs(self) -> tuple[str, ...]:
        return (self.x, self.y)

    @property
    def feedback(self) -> bool:
        return self.x.startswith("sensor.") or self.y.startswith("sensor.")


def _map_kind(value) -> type:
    return GridMapSpec if isinstance(value, dict) and "grid" in value else LinearMapSpec


MapSpec.choices = (LinearMapSpec, GridMapSpec)
dispatch(MapSpec, _map_kind)


class TransitionSpec(Spec, kw_only=True):
    """Leave the state for ``to`` after ``after`` s in it and/or when ``when`` holds:
    one condition, or a list of conditions that must all hold at once (the swing foot
    down *and* the body past the take-off board)."""

    to: str
    after: Num("time") | None = None  # s since entering the state
    when: ConditionSpec | list[ConditionSpec] | None = None
    # s the `when` must have held without a break (a flickering contact is no take-off)
    held: Num("time") | None = field(name="for", default=None)

    def __post_init__(self):
        if self.after is None and self.when is None:
            raise ValueError("a transition needs 'after' (s) and/or 'when' (a condition); "
                             "key transitions are keys with 'goto'")
        if isinstance(self.when, list) and not self.when:
            raise ValueError("'when' is an empty list: give one condition, or several "
                             "that must all hold")
        if self.held is not None and self.when is None:
            raise at("for", "'for' (s) is how long 'when' must have held: it needs 'when'")

    @property
    def conditions(self) -> list[ConditionSpec]:
        """The conditions that must all hold (none without ``when``)."""
        if self.when is None:
            return []
        return list(self.when) if isinstance(self.when, list) else [self.when]


class StateSpec(Spec, kw_only=True):
    """A control state: its own keys (override the interface's) and maps (added)."""

    enter: ActionSpec | None = None
    keys: list[KeyActionSpec] = field(default_factory=list)
    maps: list[MapSpec] = field(default_factory=list)
    transitions: list[TransitionSpec] = field(default_factory=list)
    roles: str | None = None  # the role binding this state selects (which leg is the stance leg...)
    # Hz of the control steps while this state is active (faster than the interface's
    # control_rate: a take-off's, a landing's sensors polled every step); None: the interface's
    control_rate: Annotated[float, Meta(ge=1.0, le=10000.0)] | None = None
    description: str = ""


class AnyStateSpec(Spec, kw_only=True):
    """Keys and transitions of a machine that hold in every one of its states (a
    transition never fires from the state it leads to); a state's own keys win."""

    keys: list[KeyActionSpec] = field(default_factory=list)
    transitions: list[TransitionSpec] = field(default_factory=list)


class MachineSpec(Spec, kw_only=True):
    """A named state machine running beside the others (one per limb, a gait machine
    beside a grasp machine): its own states, start state and ``any_state`` rules."""

    states: Annotated[dict[str, StateSpec], Meta(min_length=1)]
    initial: str | None = None  # starting state; default the first
    any_state: AnyStateSpec = field(default_factory=AnyStateSpec)
    description: str = ""

    @property
    def start_state(self) -> str:
        return self.initial if self.initial is not None else next(iter(self.states))


MAIN_MACHINE = "main"  # the name of the machine of the top-level ``states:``


class GestureSpec(Spec, kw_only=True):
    """A recorded mouse performance bound to a key: pressing the key plays ``path``
    back through the active mouse maps, in sim time, as a sequence plays its poses."""

    key: str
    description: str = ""
    # [t, x, y] points: t s since the key press (increasing), x and y the mouse position 0..1 (y up)
    path: Annotated[list[tuple[Num("input"), Num("input"), Num("input")]], Meta(min_length=1)]

    @property
    def duration(self) -> float:
        return self.path[-1][0]


class GamepadSpec(Spec, kw_only=True):
    """How a gamepad's sticks and triggers read: dead zones, as a fraction of the
    travel. Inside a dead zone an input reads 0; beyond it the rest of the travel is
    stretched back to the full range, so there is no jump at its edge."""

    dead_zone: Annotated[float, Meta(ge=0.0, lt=1.0)] = 0.12  # sticks (-1..1)
    trigger_dead_zone: Annotated[float, Meta(ge=0.0, lt=1.0)] = 0.05  # triggers (0..1)
    # the stick that moves the inputs pointer.x / pointer.y, as the mouse does
    pointer: Literal["left", "right"] = "left"


class InterfaceSpec(Spec, kw_only=True):
    name: str
    description: str
    character: str
    # one line for a newcomer, shown on the HUD: where to hold the mouse, which keys, what rhythm
    how_to_play: str = ""
    scene: str = "flat"
    slowdown: Annotated[float, Meta(ge=1.0, le=100.0)] = 1.0
    app_keys: dict[str, str] = field(default_factory=dict)  # rebind the app's keys: action -> key
    gains: dict[str, GainSpec] = field(default_factory=dict)
    poses: dict[str, PoseSpec] = field(default_factory=dict)
    sequences: dict[str, list[SequenceStepSpec]] = field(default_factory=dict)
    chains: dict[str, ChainSpec] = field(default_factory=dict)
    maps: list[MapSpec] = field(default_factory=list)  # always active
    modes: dict[str, list[MapSpec]] = field(default_factory=dict)  # control modes: name -> maps
    mode: str | None = None  # starting mode; default the first
    # a pose (plain degrees) the figure is built in at the start, over the character's start joints:
    # hanging from a bar, arms up
    start_pose: str | None = None
    # the root link's angle at the start (deg from upright, counter-clockwise positive), over the
    # character's: 90 lies a figure facing +x on its back
    start_angle: Angle | None = None
    keys: list[KeyActionSpec] = field(default_factory=list)
    states: dict[str, StateSpec] = field(default_factory=dict)
    gestures: list[GestureSpec] = field(default_factory=list)  # recorded mouse paths bound to keys
    initial: str | None = None  # starting state; default the first
    # keys and transitions of every state
    any_state: AnyStateSpec = field(default_factory=AnyStateSpec)
    # more state machines, side by side with 'states' (the machine 'main')
    machines: dict[str, MachineSpec] = field(default_factory=dict)
    perturbation: PerturbSpec = field(default_factory=PerturbSpec)
    tracking: TrackingSpec | None = None  # how mocap channels drive the figure (track actions)
    # role -> binding -> joint or link: names that mean one joint or link in one binding and another
    # in the next (a state's 'roles')
    roles: dict[str, dict[str, str]] = field(default_factory=dict)
    binding: str | None = None  # the starting role binding; default the first
    # Hz at which sensor conditions are checked
    control_rate: Annotated[float, Meta(ge=1.0, le=10000.0)] = 60.0
    # dead zones of the gamepad's sticks and triggers
    gamepad: GamepadSpec = field(default_factory=GamepadSpec)
    # s of simulated time between automatic checkpoints (the rewind's keyframes)
    checkpoint_every: Annotated[float, Meta(ge=CHECKPOINT_MIN,
                                            le=CHECKPOINT_MAX)] = CHECKPOINT_EVERY

    def __post_init__(self):
        for name, steps in self.sequences.items():
            if not steps:
                raise at("sequences", f"sequence '{name}' has no steps")

    def app_key_table(self) -> dict[str, str]:
        """App action -> key, after this interface's rebinding."""
        table = {action: key for action, (key, _) in APP_KEYS.items()}
        table.update({a: normalize_key(k) for a, k in self.app_keys.items()})
        return table

    def start_character(self, character):
        """The character as this interface starts it: its start joints overlaid with the
        ``start_pose``'s, its root at ``start_angle`` (the character itself when there is
        neither)."""
        if self.start_pose is None and self.start_angle is None:
            return character
        joints = dict(character.start.joints)
        if self.start_pose is not None:
            joints.update(self.poses[self.start_pose].joint_degrees())
        update = {"joints": joints}
        if self.start_angle is not None:
            update["angle"] = self.start_angle
        return character.model_copy(
            update={"start": character.start.model_copy(update=update)})

    @property
    def start_mode(self) -> str | None:
        return self.mode if self.mode is not None else next(iter(self.modes), None)

    @property
    def start_state(self) -> str | None:
        return self.initial if self.initial is not None else next(iter(self.states), None)

    @property
    def bindings(self) -> list[str]:
        """The role bindings' names (those of the first role; all roles share them)."""
        for targets in self.roles.values():
            return list(targets)
        return []

    @property
    def start_binding(self) -> str | None:
        return self.binding if self.binding is not None else next(iter(self.bindings), None)

    def renamer(self, binding: str | None):
        """``name -> the joint or link it means`` under ``binding`` (itself unless a role)."""
        roles = self.roles
        if not roles or binding is None:
            return lambda name: name
        return lambda name: roles[name][binding] if name in roles else name

    def state_machines(self) -> dict[str, MachineSpec]:
        """Every state machine by name, in the order they run: the top-level ``states``
        (as machine 'main') first, then ``machines``."""
        out: dict[str, MachineSpec] = {}
        if self.states:
            out[MAIN_MACHINE] = MachineSpec(
                states=self.states, initial=self.initial, any_state=self.any_state,
                description="")
        out.update(self.machines)
        return out

    def resolve_goto(self, name: str, machine: str | None = None) -> tuple[str, str] | None:
        """(machine, state) a ``goto`` names: MACHINE.STATE, else a state of ``machine``
        (the machine the action belongs to), else the one machine with such a state.
        None if there is no such state or the name is ambiguous."""
        machines = self.state_machines()
        head, dot, tail = name.partition(".")
        if dot and head in machines and tail in machines[head].states:
            return head, tail
        if machine is not None and name in machines.get(machine, MachineSpec(
                states={})).states:
            return machine, name
        found = [m for m, spec in machines.items() if name in spec.states]
        return (found[0], name) if len(found) == 1 else None


def _check_keys(spec: InterfaceSpec, located: Located) -> None:
    for action, key in spec.app_keys.items():
        if action not in APP_KEYS:
            raise located.error(("app_keys", action),
                                f"unknown app action '{action}'; expected one of: "
                                f"{', '.join(APP_KEYS)}", prefer_key=True)
        if key_problem(key):
            raise located.error(("app_keys", action), key_problem(key))
    named = [(("keys", i, "key"), k.key) for i, k in enumerate(spec.keys)]
    named += [(("states", n, "keys", i, "key"), k.key) for n, state in spec.states.items()
              for i, k in enumerate(state.keys)]
    named += [(("gestures", i, "key"), g.key) for i, g in enumerate(spec.gestures)]
    named += [(loc, k.key) for loc, k in machine_keys(spec)]
    for loc, key in named:
        if key_problem(key):
            raise located.error(loc, key_problem(key))
    _check_buffers(spec, located)
    app_table = spec.app_key_table()
    by_key: dict[str, str] = {}
    for action, key in app_table.items():
        if key in by_key:
            raise located.error(("app_keys",), f"app actions '{by_key[key]}' and '{action}' "
                                               f"are both on key '{key}'")
        by_key[key] = f"app:{action}"
    lists = [(("keys",), spec.keys)] + [(("states", name, "keys"), state.keys)
                                        for name, state in spec.states.items()]
    lists += [(("any_state", "keys"), spec.any_state.keys)]
    for mname, machine in spec.machines.items():
        lists += [(("machines", mname, "states", name, "keys"), state.keys)
                  for name, state in machine.states.items()]
        lists += [(("machines", mname, "any_state", "keys"), machine.any_state.keys)]
    for where, bindings in lists:
        seen: dict[str, int] = {}
        for i, binding in enumerate(bindings):
            key = normalize_key(binding.key)
            loc = where + (i, "key")
            owner = by_key.get(key)
            if owner is not None:
                action = owner[4:]
                if binding.app == action:  # binding the app's own action to its own key
                    raise located.error(loc, f"key '{key}' is already the app's '{action}' "
                                             f"key: delete this binding (it does that "
                                             f"without one), or move the app's with "
                                             f"app_keys: {{{action}: <key>}}")
                raise located.error(loc, f"key '{key}' is the app's '{action}' key; bind "
                                         f"another key or move the app's with app_keys: "
                                         f"{{{action}: <key>}}")
            if key in seen:
                scope = "" if where == ("keys",) else f" in state '{where[1]}'"
                raise located.error(loc, f"key '{key}' is bound twice{scope} (also "
                                         f"{'.'.join(map(str, where))}[{seen[key]}])")
            seen[key] = i


def _check_buffers(spec: InterfaceSpec, located: Located) -> None:
    """``buffer`` keeps a press for a state entered later: a key bound in every state
    (top-level ``keys``, ``any_state``) never waits for one."""
    always = [(("keys", i, "buffer"), k) for i, k in enumerate(spec.keys)]
    always += [(("any_state", "keys", i, "buffer"), k)
               for i, k in enumerate(spec.any_state.keys)]
    always += [(("machines", m, "any_state", "keys", i, "buffer"), k)
               for m, machine in spec.machines.items()
               for i, k in enumerate(machine.any_state.keys)]
    for loc, k in always:
        if k.buffer is not None:
            where = "top-level keys" if loc[0] == "keys" else "any_state keys"
            raise located.error(loc, f"'buffer' keeps an early press for a state's key, "
                                     f"but {where} are bound in every state: move key "
                                     f"'{k.key}' into the states that take it, or drop "
                                     f"'buffer'", prefer_key=True)


def machine_keys(spec: InterfaceSpec):
    """(location, key action) of the keys of ``any_state`` and of the extra machines."""
    for i, k in enumerate(spec.any_state.keys):
        yield ("any_state", "keys", i, "key"), k
    for mname, machine in spec.machines.items():
        for sname, state in machine.states.items():
            for i, k in enumerate(state.keys):
                yield ("machines", mname, "states", sname, "keys", i, "key"), k
        for i, k in enumerate(machine.any_state.keys):
            yield ("machines", mname, "any_state", "keys", i, "key"), k


def gesture_problems(spec: InterfaceSpec, gestures=None):
    """(location, message) of each problem with ``gestures`` (default: the spec's) in
    ``spec``: times must start at >= 0 and increase, x and y lie in 0..1, and a key
    may be bound once (not an app key, nor a key of ``keys`` or of a state)."""
    gestures = spec.gestures if gestures is None else gestures
    by_key = {key: f"the app's '{action}' key" for action, key in spec.app_key_table().items()}
    for i, k in enumerate(spec.keys):
        by_key.setdefault(normalize_key(k.key), f"bound in keys[{i}]")
    for name, state in spec.states.items():
        for i, k in enumerate(state.keys):
            by_key.setdefault(normalize_key(k.key), f"bound in state '{name}' (keys[{i}])")
    for loc, k in machine_keys(spec):
        by_key.setdefault(normalize_key(k.key), f"bound in {'.'.join(map(str, loc[:-1]))}")
    for i, g in enumerate(gestures):
        loc = ("gestures", i)
        last = None
        for j, (t, x, y) in enumerate(g.path):
            if t < 0 or (last is not None and t <= last):
                yield loc + ("path", j, 0), (f"gesture time {t:g} s must be "
                                              + ("0 or more" if last is None else
                                                 f"after the previous point's {last:g} s"))
            elif t > GESTURE_SECONDS:
                yield loc + ("path", j, 0), (f"gesture time {t:g} s is past the longest "
                                              f"gesture, {GESTURE_SECONDS:g} s")
            for c, v in ((1, x), (2, y)):
                if not 0.0 <= v <= 1.0:
                    yield loc + ("path", j, c), (f"gesture {'xy'[c - 1]} = {v:g} is outside "
                                                 "0..1 (mouse positions are normalised)")
            last = t
        key = normalize_key(g.key)
        if key in by_key:
            yield loc + ("key",), f"key '{key}' of a gesture is {by_key[key]}"
        by_key[key] = f"the key of gestures[{i}]"


def _check_gestures(spec: InterfaceSpec, located: Located) -> None:
    for loc, message in gesture_problems(spec):
        raise located.error(loc, message)


def with_gesture(spec: InterfaceSpec, key: str, path, description: str = "") -> InterfaceSpec:
    """``spec`` with a gesture bound to ``key`` (replacing a gesture already there).
    ValueError (one line) if the gesture is invalid or the key is taken."""
    from puppet.data.validate import located_data

    key = normalize_key(key)
    try:
        gesture = validate(located_data({"key": key, "path": [list(p) for p in path],
                                         "description": description}, "gesture"),
                           GestureSpec)
    except DataError as exc:
        raise ValueError(f"bad gesture: {exc.message}") from None
    gestures = [g for g in spec.gestures if normalize_key(g.key) != key] + [gesture]
    for _, message in gesture_problems(spec, gestures):
        raise ValueError(message)
    return spec.model_copy(update={"gestures": gestures})


def check_against_character(spec: InterfaceSpec, character: CharacterSpec,
                            located: Located) -> None:
    """Joint, link and chain references must fit the interface's character."""
    from puppet.data.interface_refs import check_character_refs

    check_character_refs(spec, character, located)


def parse_interface(located: Located) -> InterfaceSpec:
    from puppet.data.interface_refs import check_names

    spec = validate(located, InterfaceSpec)
    _check_keys(spec, located)
    _check_gestures(spec, located)
    check_names(spec, located)
    return spec


def load_interface(path) -> tuple[InterfaceSpec, Located]:
    located = load_file(path)
    return parse_interface(located), located
