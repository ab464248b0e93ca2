"""The action vocabulary of interface files: poses, sequences, conditions, reaches, grasps.

These are the paper's "action semantics" written as data. A key, a state's entry or
a transition runs one ``ActionSpec``; every field it sets is one action, and they run
in a fixed order (see ``puppet.interface.runtime``). Angles are degrees, times
seconds, lengths metres.
"""

from __future__ import annotations

import re
from typing import Annotated, Literal, Union

from pydantic import Discriminator, Field, Tag, field_validator, model_validator

from puppet.data.ranges import (Angle, AngleChange, Damping, Duration, Friction, Gravity,
                                ModelXY, Num, PositiveDuration, Seed, Stiffness, Torque,
                                WorldXY)
from puppet.data.keys import APP_KEYS, GAMEPAD_BUTTONS
from puppet.data.validate import Spec

InputXY = tuple[Num("input"), Num("input")]


# Continuous inputs a map may read. Mouse position is 0..1 (y up), buttons 0/1,
# gamepad axes -1..1 and buttons 0/1, plugin channels whatever the plugin sends.
INPUT_PATTERNS = (
    ("mouse.x", r"mouse\.x"),
    ("mouse.y", r"mouse\.y"),
    ("mouse.left / mouse.middle / mouse.right", r"mouse\.(left|middle|right)"),
    ("gamepad.left_x / left_y / right_x / right_y (-1..1, y up)",
     r"gamepad\.(left|right)_[xy]"),
    ("gamepad.left_trigger / right_trigger (0..1)", r"gamepad\.(left|right)_trigger"),
    ("gamepad.a / b / x / y / start / back / left_shoulder / right_shoulder / dpad_up ...",
     r"gamepad\.(" + "|".join(GAMEPAD_BUTTONS) + ")"),
    ("gamepad.axisN / gamepad.buttonN (a joystick with no controller mapping)",
     r"gamepad\.(axis|button)\d+"),
    ("channel.NAME", r"channel\.[A-Za-z_][A-Za-z0-9_.-]*"),
    ("sensor.SENSOR (e.g. sensor.com.vx, sensor.angle.chest)", r"sensor\.[A-Za-z_][A-Za-z0-9_.-]*"),
)


def check_input_name(name: str) -> str:
    for _, pattern in INPUT_PATTERNS:
        if re.fullmatch(pattern, name):
            return name
    raise ValueError(f"unknown input '{name}'; expected one of: "
                     f"{', '.join(label for label, _ in INPUT_PATTERNS)}")


# App actions a key may trigger through ``app:``. Window-side ones come back from
# Session.handle; sim-side ones (SIM_ACTIONS) the session performs.
META_APP_ACTIONS = tuple(a for a in APP_KEYS if a != "quit")


class FrameTargetSpec(Spec):
    """A joint's target given as the angle of one of its two links in the world
    (``world``) or relative to another link (``relative_to`` and ``angle``), degrees,
    re-solved from the figure's state at the control rate. ``hold`` says which of the
    joint's links that angle is for: its child (default: a thigh held at 20 deg in the
    world through the hip) or its parent (the trunk held upright through the stance
    hip, whose child, the stance thigh, stands on the ground)."""

    world: Angle | None = Field(None, description="deg from the model's orientation")
    relative_to: str | None = Field(None, description="a link")
    angle: Angle | None = Field(None, description="deg, with relative_to")
    hold: Literal["child", "parent"] = "child"

    @model_validator(mode="after")
    def _check(self):
        if (self.world is None) == (self.relative_to is None):
            raise ValueError("a frame target needs exactly one of 'world' (deg) or "
                             "'relative_to' (a link, with 'angle')")
        if self.relative_to is not None and self.angle is None:
            raise ValueError("'relative_to' needs 'angle' (deg)")
        if self.world is not None and self.angle is not None:
            raise ValueError("'angle' goes with 'relative_to'; with 'world' the angle is "
                             "the value of 'world'")
        return self


def _target_kind(value) -> str:
    return "<frame>" if isinstance(value, (dict, FrameTargetSpec)) else "<deg>"


Target = Annotated[Union[Annotated[Angle, Tag("<deg>")],
                         Annotated[FrameTargetSpec, Tag("<frame>")]], Discriminator(_target_kind)]


class PoseSpec(Spec):
    """A full or partial pose: joint targets, optionally with gains for those joints.
    A target is degrees of the joint, or a ``FrameTargetSpec`` ({world: deg} ...)."""

    joints: dict[str, Target] = Field(description="joint -> target, degrees")
    stiffness: dict[str, Stiffness] = Field(default_factory=dict)
    damping: dict[str, Damping] = Field(default_factory=dict)
    max_torque: dict[str, Torque] = Field(default_factory=dict,
                                          description="joint -> N*m the servo may give")

    def joint_degrees(self) -> dict[str, float]:
        """The targets given as joint angles (degrees); frame targets left out."""
        return {j: v for j, v in self.joints.items() if isinstance(v, (int, float))}
    description: str = ""


class SequenceStepSpec(Spec):
    pose: str
    hold: PositiveDuration = Field(description="s the pose is held before the next step")


class ConditionSpec(Spec):
    """A test on one named sensor: ``above``/``below`` a threshold, or ``is`` for contact.

    Sensors: joint.JOINT (deg), angle.LINK (deg, world, -180..180), root.angle (deg,
    -180..180), lean (deg of
    the root-to-centre-of-mass line from vertical, + toward +x), com.x, com.y (m),
    com.vx, com.vy (m/s), height.LINK (m, link centre), contact.LINK (true/false),
    channel.NAME (an input channel, in the plugin's units: a mocap channel).
    """

    sensor: str
    above: Num("sensor") | None = None
    below: Num("sensor") | None = None
    is_: bool | None = Field(None, alias="is")

    @model_validator(mode="after")
    def _check(self):
        contact = self.sensor.startswith("contact.")
        if contact:
            if self.is_ is None or self.above is not None or self.below is not None:
                raise ValueError(f"'{self.sensor}' is true or false: write 'is: true' or "
                                 "'is: false' (not above/below)")
        else:
            if self.is_ is not None:
                raise ValueError(f"'is' only applies to contact.LINK sensors; use above/below "
                                 f"for '{self.sensor}'")
            if self.above is None and self.below is None:
                raise ValueError("a condition needs 'above' and/or 'below'")
            if self.above is not None and self.below is not None and self.above >= self.below:
                raise ValueError(f"'above' ({self.above}) must be less than 'below' "
                                 f"({self.below})")
        return self


class ChainSpec(Spec):
    """Two or more actuated joints in a row (an arm; a leg with hip, knee and ankle) and
    an end point on the last joint's child link."""

    joints: list[str] = Field(min_length=2, max_length=32, description="proximal joint first")
    end: ModelXY = Field(description="end effector, model frame, m")
    description: str = ""


class PropPointSpec(Spec):
    """A grasp point of a scene prop, picked relative to what a chain holds: ``offset``
    0 is the point nearest the chain's end (the one it holds, if it holds one), 1 the
    next in the prop's order, -1 the previous, 2 the one after next."""

    prop: str
    offset: int = Field(0, ge=-20, le=20)
    of: str | None = Field(None, description="the chain whose hold counts from (default: "
                                             "the reaching chain)")


class SteerSpec(Spec):
    """A target steered by two continuous inputs: x and y map linearly (clamped) from
    their input ranges onto ``x_to`` / ``y_to`` metres in the reach's frame."""

    x: str = "mouse.x"
    y: str = "mouse.y"
    x_from: InputXY = (0.0, 1.0)
    y_from: InputXY = (0.0, 1.0)
    x_to: WorldXY = Field(description="m at x_from[0] and x_from[1]")
    y_to: WorldXY = Field(description="m at y_from[0] and y_from[1]")

    _check_inputs = field_validator("x", "y")(lambda cls, v: check_input_name(v))

    @model_validator(mode="after")
    def _check(self):
        if self.x_from[0] == self.x_from[1] or self.y_from[0] == self.y_from[1]:
            raise ValueError("'x_from' and 'y_from' must each be two different input values")
        return self


class ReachSpec(Spec):
    """Move a chain's end toward a target along a Hermite-eased path, IK every step. The
    target is a fixed point (``target``, in ``frame``), a scene prop's grasp point
    (``point``, followed as the prop moves) or steered by two inputs (``steer``)."""

    chain: str
    target: WorldXY | None = Field(None, description="m; in 'frame' coordinates")
    point: PropPointSpec | None = None
    steer: SteerSpec | None = None
    frame: Literal["world", "root"] = Field(
        "root", description="root: relative to the root link at the moment of the key "
                            "(for steer: as it moves)")
    duration: PositiveDuration = Field(0.5, description="s from start to target")
    hold: Duration = Field(0.0, description="s to keep re-solving at the target "
                                            "(a steered reach is held until preempted)")
    grasp: bool = Field(False, description="grasp the target when the end gets within "
                                           "tolerance")
    tolerance: Num("tolerance") = Field(0.04, description="m, for grasp")
    rigid: bool = Field(False, description="with grasp: also hold the end link's angle "
                                           "to what it grasps (GraspSpec.rigid)")
    max_torque: Torque | None = Field(None, description="N*m a rigid grasp holds the "
                                                        "angle with (default: no limit)")

    @model_validator(mode="after")
    def _check(self):
        given = [n for n in ("target", "point", "steer") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("a reach needs exactly one of 'target' (a point), 'point' (a "
                             "prop's grasp point) or 'steer' (two inputs)"
                             + (f"; got {' and '.join(given)}" if given else ""))
        _check_rigid(self, "a reach with 'grasp: true'" if not self.grasp else None)
        return self


def _check_rigid(spec, needs: str | None) -> None:
    if needs is not None and spec.rigid:
        raise ValueError(f"'rigid' holds a grasp's angle: it needs {needs}")
    if spec.max_torque is not None and not spec.rigid:
        raise ValueError("'max_torque' limits a rigid grasp: add 'rigid: true'")


class GraspSpec(Spec):
    """Arm a grasp: the chain's end holds the first of ``points`` (world) it comes within
    ``tolerance`` of, pinned to the world; or the nearest grasp point or segment of
    ``prop`` (a scene prop's name, or ``any``) within ``tolerance``, pinned to the prop,
    which may move."""

    chain: str
    points: list[WorldXY] | None = Field(None, min_length=1, description="world points, m")
    prop: str | None = Field(None, description="a scene prop, or 'any'")
    tolerance: Num("tolerance") = Field(0.04, description="m")
    within: Num("positive_duration") | None = Field(None, description="s the grasp stays armed; "
                                                           "default until released")
    rigid: bool = Field(False, description="also hold the end link's angle to the prop "
                                           "(the world) as it is at the catch: a grip "
                                           "that does not turn about the point")
    max_torque: Torque | None = Field(None, description="N*m a rigid grasp holds the "
                                                        "angle with (default: no limit)")

    @model_validator(mode="after")
    def _check(self):
        if (self.points is None) == (self.prop is None):
            raise ValueError("a grasp needs exactly one of 'points' (world points) or "
                             "'prop' (a scene prop's grasp points)")
        _check_rigid(self, None)
        return self


class ShoveSpec(Spec):
    """A shove: an impulse (N*s, world x and y) at a point of a link (model frame, m;
    default the link's centre of mass) - to try how a figure takes a push."""

    link: str
    impulse: tuple[Num("shove"), Num("shove")]
    point: ModelXY | None = None


class ActionSpec(Spec):
    """Everything one trigger (key, state entry) can do."""

    pose: str | None = Field(None, description="set a named pose absolutely")
    set: dict[str, Target] = Field(default_factory=dict, description="joint -> deg, or "
                                                                     "{world: deg} ...")
    adjust: dict[str, AngleChange] = Field(default_factory=dict, description="joint -> +deg")
    sequence: str | None = Field(None, description="start a named pose sequence")
    repeat: int | Literal["forever"] | None = Field(
        None, description="play the sequence this many times (or until preempted)")
    stiffness: dict[str, Stiffness] = Field(default_factory=dict)
    damping: dict[str, Damping] = Field(default_factory=dict)
    while_held: bool = Field(False, description="undo the stiffness/damping changes "
                                                "when the key is released")
    mode: str | None = Field(None, description="select a control mode (map set)")
    goto: str | None = Field(None, description="go to a state (MACHINE.STATE for a state "
                                               "of another machine)")
    reach: ReachSpec | None = None
    grasp: GraspSpec | None = None
    release: str | None = Field(None, description="chain name, or 'all'")
    app: str | None = Field(None, description="an app action: " + ", ".join(META_APP_ACTIONS))
    slowdown: float | None = Field(None, ge=1.0, le=100.0)
    gravity: Gravity | None = Field(None, description="m/s^2")
    friction: Friction | None = Field(None, description="ground friction")
    perturb: Literal["on", "off", "toggle"] | None = None
    push: ShoveSpec | None = Field(None, description="shove a link (an impulse)")
    track: Literal["off", "angles", "kd"] | None = Field(
        None, description="follow the performer (the interface's 'tracking'): joint "
                          "angles, KD control, or stop")
    kinematic: Literal["on", "off", "toggle"] | None = Field(
        None, description="KD control's Cartesian pulls (off: free fall)")
    description: str = ""

    @field_validator("app")
    @classmethod
    def _app(cls, value):
        if value is not None and value not in META_APP_ACTIONS:
            raise ValueError(f"unknown app action '{value}'; expected one of: "
                             f"{', '.join(META_APP_ACTIONS)}")
        return value

    @model_validator(mode="after")
    def _check_repeat(self):
        if self.repeat is not None:
            if self.sequence is None:
                raise ValueError("'repeat' repeats a sequence, but this action starts none")
            if isinstance(self.repeat, int) and not 1 <= self.repeat <= 10000:
                raise ValueError(f"'repeat' {self.repeat} must be 1..10000 or 'forever'")
        return self

    def touched_joints(self) -> set[str]:
        return set(self.set) | set(self.adjust)


class KeyActionSpec(ActionSpec):
    """What a key (or gamepad/mouse button, e.g. ``gamepad.button0``) does when pressed."""

    key: str


class PerturbSpec(Spec):
    """Small random kicks: every ``every`` s each link gets an angular impulse."""

    impulse: Num("impulse") = Field(0.002, description="N*m*s, standard deviation")
    every: Num("period") = Field(0.1, description="s")
    seed: Seed = 0
    start_on: bool = False
