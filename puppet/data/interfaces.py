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

from typing import Annotated, Literal, Union

from pydantic import Discriminator, Field, Tag, field_validator, model_validator

from puppet.data.actions import (ActionSpec, ChainSpec, ConditionSpec,
                                 KeyActionSpec, PerturbSpec, PoseSpec, SequenceStepSpec,
                                 check_input_name)
from puppet.data.characters import CharacterSpec
from puppet.data.ranges import AngleChange, Damping, Num, Stiffness, Torque
from puppet.data.validate import Spec, validate
from puppet.data.yamlfile import Located, load_file
from puppet.interface.app_keys import APP_KEYS, key_problem, normalize_key

__all__ = ["InterfaceSpec", "LinearMapSpec", "GridMapSpec",
           "KeyActionSpec", "StateSpec", "GestureSpec", "load_interface", "parse_interface",
           "check_against_character", "with_gesture"]


CHECKPOINT_EVERY = 3.0  # s of simulated time between automatic checkpoints (keyframes)
CHECKPOINT_MIN, CHECKPOINT_MAX = 0.5, 600.0  # s; the interval is a multiple of 0.5 s
MIN_SLOWDOWN, MAX_SLOWDOWN = 0.1, 100.0
GESTURE_SECONDS = 600.0  # the longest gesture  # wall s per simulated s; 0.1: ten times faster


class GainSpec(Spec):
    stiffness: Stiffness | None = None
    damping: Damping | None = None
    max_torque: Torque | None = None


class PowerCurve(Spec):
    power: Num("power")


Curve = Union[Literal["linear", "smoothstep"], PowerCurve]


class LinearMapSpec(Spec):
    """u = (input - from[0]) / (from[1] - from[0]), clamped to 0..1 (clamp), shaped by
    ``curve``; value = to[0] + u * (to[1] - to[0]) degrees; each joint's target is
    gain * value (``joint`` is ``joints: {joint: 1}``)."""

    input: str = Field(description="mouse.x (0 left .. 1 right), mouse.y (0 bottom .. 1 "
                                   "top), mouse.left, gamepad.axisN, channel.NAME ...")
    joint: str | None = None
    joints: dict[str, Num("coupling")] = Field(
        default_factory=dict, description="coupling: joint -> gain (sign = mirror)")
    from_: tuple[Num("input"), Num("input")] = Field((0.0, 1.0), alias="from")
    to: tuple[AngleChange, AngleChange] = Field(description="degrees at from[0] and from[1]")
    clamp: bool = True
    curve: Curve = "linear"

    _check_input = field_validator("input")(lambda cls, v: check_input_name(v))

    @model_validator(mode="after")
    def _check(self):
        if self.from_[0] == self.from_[1]:
            raise ValueError("'from' must be two different input values")
        if (self.joint is None) == (not self.joints):
            raise ValueError("a map needs exactly one of 'joint' (one joint) or 'joints' "
                             "(joint -> gain)")
        return self

    def gains(self) -> dict[str, float]:
        return {self.joint: 1.0} if self.joint is not None else dict(self.joints)

    @property
    def inputs(self) -> tuple[str, ...]:
        return (self.input,)


class GridMapSpec(Spec):
    """Bilinear interpolation over a grid of named poses (the paper's cat trot).

    ``grid`` rows go top (y = 1) to bottom (y = 0), columns left (x = 0) to right
    (x = 1); the pose targets of the four nearest poses are blended."""

    grid: list[list[str]] = Field(min_length=1)
    x: str = "mouse.x"
    y: str = "mouse.y"
    joints: list[str] | None = Field(
        None, description="drive only these of the poses' joints (default: all); with "
                          "several maps over one grid, each limb can have its own map")
    mirror: list[Literal["x", "y"]] = Field(
        default_factory=list, description="flip these inputs (u -> 1 - u) before the "
                                          "lookup: [x, y] reflects the input through the "
                                          "grid's centre, half a cycle out of phase for "
                                          "a circling mouse")

    _check_inputs = field_validator("x", "y")(lambda cls, v: check_input_name(v))

    @model_validator(mode="after")
    def _check(self):
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
        return self

    @property
    def inputs(self) -> tuple[str, ...]:
        return (self.x, self.y)


def _map_kind(value) -> str:
    if isinstance(value, dict):
        return "<grid>" if "grid" in value else "<linear>"
    return "<grid>" if isinstance(value, GridMapSpec) else "<linear>"


MapSpec = Annotated[Union[Annotated[LinearMapSpec, Tag("<linear>")],
                          Annotated[GridMapSpec, Tag("<grid>")]], Discriminator(_map_kind)]


class TransitionSpec(Spec):
    """Leave the state for ``to`` after ``after`` s in it and/or when ``when`` holds."""

    to: str
    after: Num("time") | None = Field(None, description="s since entering the state")
    when: ConditionSpec | None = None

    @model_validator(mode="after")
    def _check(self):
        if self.after is None and self.when is None:
            raise ValueError("a transition needs 'after' (s) and/or 'when' (a condition); "
                             "key transitions are keys with 'goto'")
        return self


class StateSpec(Spec):
    """A control state: its own keys (override the interface's) and maps (added)."""

    enter: ActionSpec | None = None
    keys: list[KeyActionSpec] = Field(default_factory=list)
    maps: list[MapSpec] = Field(default_factory=list)
    transitions: list[TransitionSpec] = Field(default_factory=list)
    description: str = ""


class GestureSpec(Spec):
    """A recorded mouse performance bound to a key: pressing the key plays ``path``
    back through the active mouse maps, in sim time, as a sequence plays its poses."""

    key: str
    description: str = ""
    path: list[tuple[Num("input"), Num("input"), Num("input")]] = Field(
        min_length=1, description="[t, x, y] points: t s since the key press (increasing), "
                                  "x and y the mouse position 0..1 (y up)")

    @property
    def duration(self) -> float:
        return self.path[-1][0]


class InterfaceSpec(Spec):
    name: str
    description: str
    character: str
    scene: str = "flat"
    slowdown: float = Field(1.0, ge=1.0, le=100.0)
    app_keys: dict[str, str] = Field(default_factory=dict,
                                     description="rebind the app's keys: action -> key")
    gains: dict[str, GainSpec] = Field(default_factory=dict)
    poses: dict[str, PoseSpec] = Field(default_factory=dict)
    sequences: dict[str, list[SequenceStepSpec]] = Field(default_factory=dict)
    chains: dict[str, ChainSpec] = Field(default_factory=dict)
    maps: list[MapSpec] = Field(default_factory=list, description="always active")
    modes: dict[str, list[MapSpec]] = Field(default_factory=dict,
                                            description="control modes: name -> maps")
    mode: str | None = Field(None, description="starting mode; default the first")
    keys: list[KeyActionSpec] = Field(default_factory=list)
    states: dict[str, StateSpec] = Field(default_factory=dict)
    gestures: list[GestureSpec] = Field(default_factory=list,
                                        description="recorded mouse paths bound to keys")
    initial: str | None = Field(None, description="starting state; default the first")
    perturbation: PerturbSpec = Field(default_factory=PerturbSpec)
    control_rate: float = Field(60.0, ge=1.0, le=10000.0,
                                description="Hz at which sensor conditions are checked")
    checkpoint_every: float = Field(CHECKPOINT_EVERY, ge=CHECKPOINT_MIN, le=CHECKPOINT_MAX,
                                    description="s of simulated time between automatic "
                                                "checkpoints (the rewind's keyframes)")

    @field_validator("sequences")
    @classmethod
    def _non_empty(cls, value):
        for name, steps in value.items():
            if not steps:
                raise ValueError(f"sequence '{name}' has no steps")
        return value

    def app_key_table(self) -> dict[str, str]:
        """App action -> key, after this interface's rebinding."""
        table = {action: key for action, (key, _) in APP_KEYS.items()}
        table.update({a: normalize_key(k) for a, k in self.app_keys.items()})
        return table

    @property
    def start_mode(self) -> str | None:
        return self.mode if self.mode is not None else next(iter(self.modes), None)

    @property
    def start_state(self) -> str | None:
        return self.initial if self.initial is not None else next(iter(self.states), None)


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
    for loc, key in named:
        if key_problem(key):
            raise located.error(loc, key_problem(key))
    app_table = spec.app_key_table()
    by_key: dict[str, str] = {}
    for action, key in app_table.items():
        if key in by_key:
            raise located.error(("app_keys",), f"app actions '{by_key[key]}' and '{action}' "
                                               f"are both on key '{key}'")
        by_key[key] = f"app:{action}"
    lists = [(("keys",), spec.keys)] + [(("states", name, "keys"), state.keys)
                                        for name, state in spec.states.items()]
    for where, bindings in lists:
        seen: dict[str, int] = {}
        for i, binding in enumerate(bindings):
            key = normalize_key(binding.key)
            loc = where + (i, "key")
            owner = by_key.get(key)
            if owner is not None:
                action = owner[4:]
                raise located.error(loc, f"key '{key}' is the app's '{action}' key; bind "
                                         f"another key or move the app's with app_keys: "
                                         f"{{{action}: <key>}}")
            if key in seen:
                scope = "" if where == ("keys",) else f" in state '{where[1]}'"
                raise located.error(loc, f"key '{key}' is bound twice{scope} (also "
                                         f"{'.'.join(map(str, where))}[{seen[key]}])")
            seen[key] = i


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
    import pydantic

    key = normalize_key(key)
    try:
        gesture = GestureSpec(key=key, path=[tuple(p) for p in path], description=description)
    except pydantic.ValidationError as exc:
        raise ValueError(f"bad gesture: {exc.errors()[0]['msg']}") from None
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
