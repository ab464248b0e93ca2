"""The action vocabulary of interface files: poses, sequences, conditions, reaches, grasps.

These are the paper's "action semantics" written as data. A key, a state's entry or
a transition runs one ``ActionSpec``; every field it sets is one action, and they run
in a fixed order (see ``puppet.interface.runtime``). Angles are degrees, times
seconds, lengths metres.
"""

from __future__ import annotations

import re
from typing import Annotated, Literal

from puppet.data.keys import APP_KEYS, GAMEPAD_BUTTONS
from puppet.data.ranges import (
    Angle,
    AngleChange,
    Damping,
    Duration,
    Friction,
    Gravity,
    ModelXY,
    Num,
    PositiveDuration,
    Seed,
    Stiffness,
    Torque,
    WorldXY,
)
from puppet.data.validate import Meta, Spec, at, field

InputXY = tuple[Num("input"), Num("input")]


# Continuous inputs a map may read. Mouse position is 0..1 (y up), buttons 0/1,
# gamepad axes -1..1 and buttons 0/1, plugin channels whatever the plugin sends.
INPUT_PATTERNS = (
    ("mouse.x", r"mouse\.x"),
    ("mouse.y", r"mouse\.y"),
    ("mouse.left / mouse.middle / mouse.right", r"mouse\.(left|middle|right)"),
    ("pointer.x / pointer.y (the mouse, or the gamepad's pointer stick read as 0..1)",
     r"pointer\.[xy]"),
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


def check_inputs(spec, *fields: str) -> None:
    """The inputs ``spec`` names in ``fields``, checked in its ``__post_init__``: an
    unknown one is an error at that field."""
    for name in fields:
        try:
            check_input_name(getattr(spec, name))
        except ValueError as exc:
            raise at(name, str(exc)) from None


def check_input_name(name: str) -> str:
    for _, pattern in INPUT_PATTERNS:
        if re.fullmatch(pattern, name):
            return name
    raise ValueError(f"unknown input '{name}'; expected one of: "
                     f"{', '.join(label for label, _ in INPUT_PATTERNS)}")


# App actions a key may trigger through ``app:``. Window-side ones come back from
# Session.handle; sim-side ones (SIM_ACTIONS) the session performs.
META_APP_ACTIONS = tuple(a for a in APP_KEYS if a != "quit")


class FrameTargetSpec(Spec, kw_only=True):
    """A joint's target given as the angle of one of its two links in the world
    (``world``) or relative to another link (``relative_to`` and ``angle``), degrees,
    re-solved from the figure's state at the control rate. ``hold`` says which of the
    joint's links that angle is for: its child (default: a thigh held at 20 deg in the
    world through the hip) or its parent (the trunk held upright through the stance
    hip, whose child, the stance thigh, stands on the ground)."""

    world: Angle | None = None  # deg from the model's orientation
    relative_to: str | None = None  # a link
    angle: Angle | None = None  # deg, with relative_to
    hold: Literal["child", "parent"] = "child"

    def __post_init__(self):
        if (self.world is None) == (self.relative_to is None):
            raise ValueError("a frame target needs exactly one of 'world' (deg) or "
                             "'relative_to' (a link, with 'angle')")
        if self.relative_to is not None and self.angle is None:
            raise ValueError("'relative_to' needs 'angle' (deg)")
        if self.world is not None and self.angle is not None:
            raise ValueError("'angle' goes with 'relative_to'; with 'world' the angle is "
                             "the value of 'world'")


# degrees (a number) or a frame target (a mapping): msgspec tells them apart by type
Target = Angle | FrameTargetSpec


class PoseSpec(Spec, kw_only=True):
    """A full or partial pose: joint targets, optionally with gains for those joints.
    A target is degrees of the joint, or a ``FrameTargetSpec`` ({world: deg} ...)."""

    joints: dict[str, Target]  # joint -> target, degrees
    stiffness: dict[str, Stiffness] = field(default_factory=dict)
    damping: dict[str, Damping] = field(default_factory=dict)
    max_torque: dict[str, Torque] = field(default_factory=dict)  # joint -> N*m the servo may give

    def joint_degrees(self) -> dict[str, float]:
        """The targets given as joint angles (degrees); frame targets left out."""
        return {j: v for j, v in self.joints.items() if isinstance(v, (int, float))}
    description: str = ""


class ConditionSpec(Spec, kw_only=True):
    """A test on one named sensor: ``above``/``below`` a threshold, or ``is`` for contact.

    Sensors: joint.JOINT (deg), angle.LINK (deg, world, -180..180), root.angle (deg,
    -180..180), lean (deg of
    the root-to-centre-of-mass line from vertical, + toward +x), com.x, com.y (m),
    com.vx, com.vy (m/s), height.LINK (m, link centre), contact.LINK (true/false),
    held.CHAIN (m: the height of the point the chain holds; a script rule's only),
    channel.NAME (an input channel, in the plugin's units: a mocap channel).
    """

    sensor: str
    above: Num("sensor") | None = None
    below: Num("sensor") | None = None
    is_: bool | None = field(name="is", default=None)

    def __post_init__(self):
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


class SequenceStepSpec(Spec, kw_only=True):
    """One pose of a sequence, held ``hold`` s; with ``until`` (a condition, or a list
    that must all hold, as a transition's ``when``) the step ends as soon as that
    holds - tested every simulation step once ``after`` s have passed - and ``hold`` is
    the longest it waits (a push until the base leaves the floor)."""

    pose: str
    hold: PositiveDuration  # s the pose is held before the next step (with until: at most)
    until: ConditionSpec | list[ConditionSpec] | None = None
    after: Duration | None = None  # s into the step before ``until`` is tested

    def __post_init__(self):
        if isinstance(self.until, list) and not self.until:
            raise ValueError("'until' is an empty list: give one condition, or several "
                             "that must all hold")
        if self.after is not None:
            if self.until is None:
                raise at("after", "'after' (s) is when 'until' starts to be tested: it "
                                  "needs 'until'")
            if self.after >= self.hold:
                raise at("after", f"'after' ({self.after} s) must be less than 'hold' "
                                  f"({self.hold} s): the step would end before 'until' is "
                                  f"tested")

    @property
    def conditions(self) -> list[ConditionSpec]:
        """The conditions that must all hold to end the step early (none without
        ``until``)."""
        if self.until is None:
            return []
        return list(self.until) if isinstance(self.until, list) else [self.until]


class ChainSpec(Spec, kw_only=True):
    """Two or more actuated joints in a row (an arm; a leg with hip, knee and ankle) and
    an end point on the last joint's child link."""

    joints: Annotated[list[str], Meta(min_length=2, max_length=32)]  # proximal joint first
    end: ModelXY  # end effector, model frame, m
    description: str = ""


class PropPointSpec(Spec, kw_only=True):
    """A grasp point of a scene prop, picked relative to what a chain holds: ``offset``
    0 is the point nearest the chain's end (the one it holds, if it holds one), 1 the
    next in the prop's order, -1 the previous, 2 the one after next."""

    prop: str
    offset: Annotated[int, Meta(ge=-20, le=20)] = 0
    of: str | None = None  # the chain whose hold counts from (default: the reaching chain)


class SteerSpec(Spec, kw_only=True):
    """A target steered by two continuous inputs: x and y map linearly (clamped) from
    their input ranges onto ``x_to`` / ``y_to`` metres in the reach's frame."""

    x: str = "mouse.x"
    y: str = "mouse.y"
    x_from: InputXY = (0.0, 1.0)
    y_from: InputXY = (0.0, 1.0)
    x_to: WorldXY  # m at x_from[0] and x_from[1]
    y_to: WorldXY  # m at y_from[0] and y_from[1]

    def __post_init__(self):
        check_inputs(self, "x", "y")
        if self.x_from[0] == self.x_from[1] or self.y_from[0] == self.y_from[1]:
            raise ValueError("'x_from' and 'y_from' must each be two different input values")


class ReachSpec(Spec, kw_only=True):
    """Move a chain's end toward a target along a Hermite-eased path, IK every step. The
    target is a fixed point (``target``, in ``frame``), a scene prop's grasp point
    (``point``, followed as the prop moves) or steered by two inputs (``steer``)."""

    chain: str
    target: WorldXY | None = None  # m; in 'frame' coordinates
    point: PropPointSpec | None = None
    steer: SteerSpec | None = None
    # root: relative to the root link at the moment of the key (for steer: as it moves)
    frame: Literal["world", "root"] = "root"
    duration: PositiveDuration = 0.5  # s from start to target
    # s to keep re-solving at the target (a steered reach is held until preempted)
    hold: Duration = 0.0
    grasp: bool = False  # grasp the target when the end gets within tolerance
    tolerance: Num("tolerance") = 0.04  # m, for grasp
    # with grasp: also hold the end link's angle to what it grasps (GraspSpec.rigid)
    rigid: bool = False
    max_torque: Torque | None = None  # N*m a rigid grasp holds the angle with (default: no limit)

    def __post_init__(self):
        given = [n for n in ("target", "point", "steer") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("a reach needs exactly one of 'target' (a point), 'point' (a "
                             "prop's grasp point) or 'steer' (two inputs)"
                             + (f"; got {' and '.join(given)}" if given else ""))
        _check_rigid(self, "a reach with 'grasp: true'" if not self.grasp else None)


def _check_rigid(spec, needs: str | None) -> None:
    if needs is not None and spec.rigid:
        raise ValueError(f"'rigid' holds a grasp's angle: it needs {needs}")
    if spec.max_torque is not None and not spec.rigid:
        raise ValueError("'max_torque' limits a rigid grasp: add 'rigid: true'")


class GraspSpec(Spec, kw_only=True):
    """Arm a grasp: the chain's end holds the first of ``points`` (world) it comes within
    ``tolerance`` of, pinned to the world; or the nearest grasp point or segment of
    ``prop`` (a scene prop's name, or ``any``) within ``tolerance``, pinned to the prop,
    which may move."""

    chain: str
    points: Annotated[list[WorldXY], Meta(min_length=1)] | None = None  # world points, m
    prop: str | None = None  # a scene prop, or 'any'
    tolerance: Num("tolerance") = 0.04  # m
    # s the grasp stays armed; default until released
    within: Num("positive_duration") | None = None
    # also hold the end link's angle to the prop (the world) as it is at the catch: a grip that does
    # not turn about the point
    rigid: bool = False
    max_torque: Torque | None = None  # N*m a rigid grasp holds the angle with (default: no limit)
    # not the place (within tolerance) this chain last let go of: the next rung, whenever
    # the hand passes it; armed at the let-go, it cannot catch the rung it leaves
    skip_released: bool = False

    def __post_init__(self):
        if (self.points is None) == (self.prop is None):
            raise ValueError("a grasp needs exactly one of 'points' (world points) or "
                             "'prop' (a scene prop's grasp points)")
        _check_rigid(self, None)


class ShoveSpec(Spec, kw_only=True):
    """A shove: an impulse (N*s, world x and y) at a point of a link (model frame, m;
    default the link's centre of mass) - to try how a figure takes a push."""

    link: str
    impulse: tuple[Num("shove"), Num("shove")]
    point: ModelXY | None = None


class ActionSpec(Spec, kw_only=True):
    """Everything one trigger (key, state entry) can do."""

    pose: str | None = None  # set a named pose absolutely
    set: dict[str, Target] = field(default_factory=dict)  # joint -> deg, or {world: deg} ...
    over: PositiveDuration | None = None  # s: the pose's and set's targets travel there
    adjust: dict[str, AngleChange] = field(default_factory=dict)  # joint -> +deg
    sequence: str | None = None  # start a named pose sequence
    # play the sequence this many times (or until preempted)
    repeat: int | Literal["forever"] | None = None
    stiffness: dict[str, Stiffness] = field(default_factory=dict)
    damping: dict[str, Damping] = field(default_factory=dict)
    while_held: bool = False  # undo the stiffness/damping changes when the key is released
    mode: str | None = None  # select a control mode (map set)
    goto: str | None = None  # go to a state (MACHINE.STATE for a state of another machine)
    reach: ReachSpec | None = None
    grasp: GraspSpec | None = None
    release: str | None = None  # chain name, or 'all'
    app: str | None = None  # an app action: one of META_APP_ACTIONS
    slowdown: Annotated[float, Meta(ge=1.0, le=100.0)] | None = None
    gravity: Gravity | None = None  # m/s^2
    friction: Friction | None = None  # ground friction
    perturb: Literal["on", "off", "toggle"] | None = None
    push: ShoveSpec | None = None  # shove a link (an impulse)
    # follow the performer (the interface's 'tracking'): joint angles, KD control, or stop
    track: Literal["off", "angles", "kd"] | None = None
    # KD control's Cartesian pulls (off: free fall)
    kinematic: Literal["on", "off", "toggle"] | None = None
    description: str = ""

    def __post_init__(self):
        if self.app is not None and self.app not in META_APP_ACTIONS:
            raise at("app", f"unknown app action '{self.app}'; expected one of: "
                            f"{', '.join(META_APP_ACTIONS)}")
        if self.over is not None and self.pose is None and not self.set:
            raise at("over", "'over' (s) is how long the targets of 'pose' or 'set' take "
                             "to get there, but this action has neither")
        if self.repeat is not None:
            if self.sequence is None:
                raise ValueError("'repeat' repeats a sequence, but this action starts none")
            if isinstance(self.repeat, int) and not 1 <= self.repeat <= 10000:
                raise ValueError(f"'repeat' {self.repeat} must be 1..10000 or 'forever'")

    def touched_joints(self) -> set[str]:
        return set(self.set) | set(self.adjust)


class KeyActionSpec(ActionSpec, kw_only=True):
    """What a key (or gamepad/mouse button, e.g. ``gamepad.button0``) does when pressed.

    ``buffer`` (a state's key only): this binding also takes a press of its key made up
    to that many seconds before its state was entered, while no binding took the key
    (an input buffer, as fighting games keep a press made a little early)."""

    key: str
    buffer: PositiveDuration | None = None  # s a press may come before the state
    # the scenes (their names) this key is for: on any other it does nothing and the HUD and
    # the key map leave it out (default: every scene)
    scenes: list[str] = field(default_factory=list)

    def plays_on(self, scene: str | None) -> bool:
        """Whether the key acts on the scene named ``scene`` (None: any scene)."""
        return not self.scenes or scene is None or scene in self.scenes


class PerturbSpec(Spec, kw_only=True):
    """Small random kicks: every ``every`` s each link gets an angular impulse."""

    impulse: Num("impulse") = 0.002  # N*m*s, standard deviation
    every: Num("period") = 0.1  # s
    seed: Seed = 0
    start_on: bool = False
