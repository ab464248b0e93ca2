"""The action vocabulary of interface files: poses, sequences, conditions, reaches, grasps.

These are the paper's "action semantics" written as data. A key, a state's entry or
a transition runs one ``ActionSpec``; every field it sets is one action, and they run
in a fixed order (see ``puppet.interface.runtime``). Angles are degrees, times
seconds, lengths metres.
"""

from __future__ import annotations

import re
from typing import Literal

from pydantic import Field, field_validator, model_validator

from puppet.data.ranges import (Angle, AngleChange, Damping, Duration, Friction, Gravity,
                                ModelXY, Num, PositiveDuration, Seed, Stiffness, WorldXY)
from puppet.data.validate import Spec
from puppet.interface.app_keys import APP_KEYS


# Continuous inputs a map may read. Mouse position is 0..1 (y up), buttons 0/1,
# gamepad axes -1..1 and buttons 0/1, plugin channels whatever the plugin sends.
INPUT_PATTERNS = (
    ("mouse.x", r"mouse\.x"),
    ("mouse.y", r"mouse\.y"),
    ("mouse.left / mouse.middle / mouse.right", r"mouse\.(left|middle|right)"),
    ("gamepad.axisN", r"gamepad\.axis\d+"),
    ("gamepad.buttonN", r"gamepad\.button\d+"),
    ("channel.NAME", r"channel\.[A-Za-z_][A-Za-z0-9_.-]*"),
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


class PoseSpec(Spec):
    """A full or partial pose: joint targets, optionally with gains for those joints."""

    joints: dict[str, Angle] = Field(description="joint -> target, degrees")
    stiffness: dict[str, Stiffness] = Field(default_factory=dict)
    damping: dict[str, Damping] = Field(default_factory=dict)
    description: str = ""


class SequenceStepSpec(Spec):
    pose: str
    hold: PositiveDuration = Field(description="s the pose is held before the next step")


class ConditionSpec(Spec):
    """A test on one named sensor: ``above``/``below`` a threshold, or ``is`` for contact.

    Sensors: joint.JOINT (deg), angle.LINK (deg, world, -180..180), root.angle (deg,
    -180..180), lean (deg of
    the root-to-centre-of-mass line from vertical, + toward +x), com.x, com.y (m),
    com.vx, com.vy (m/s), height.LINK (m, link centre), contact.LINK (true/false).
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
    """Two actuated joints in a row and an end point on the second joint's child link."""

    joints: tuple[str, str] = Field(description="[proximal joint, distal joint]")
    end: ModelXY = Field(description="end effector, model frame, m")
    description: str = ""


class ReachSpec(Spec):
    """Move a chain's end toward a point along a Hermite-eased path, IK every step."""

    chain: str
    target: WorldXY = Field(description="m; in 'frame' coordinates")
    frame: Literal["world", "root"] = Field(
        "root", description="root: relative to the root link at the moment of the key")
    duration: PositiveDuration = Field(0.5, description="s from start to target")
    hold: Duration = Field(0.0, description="s to keep re-solving at the target")
    grasp: bool = Field(False, description="grasp the target when the end gets within "
                                           "the chain's grasp tolerance")
    tolerance: Num("tolerance") = Field(0.04, description="m, for grasp")


class GraspSpec(Spec):
    """Arm a grasp: the chain's end holds the first of ``points`` it comes within
    ``tolerance`` of (a pivot joint to the world)."""

    chain: str
    points: list[WorldXY] = Field(min_length=1, description="world points, m")
    tolerance: Num("tolerance") = Field(0.04, description="m")
    within: Num("positive_duration") | None = Field(None, description="s the grasp stays armed; "
                                                           "default until released")


class ActionSpec(Spec):
    """Everything one trigger (key, state entry) can do."""

    pose: str | None = Field(None, description="set a named pose absolutely")
    set: dict[str, Angle] = Field(default_factory=dict, description="joint -> deg")
    adjust: dict[str, AngleChange] = Field(default_factory=dict, description="joint -> +deg")
    sequence: str | None = Field(None, description="start a named pose sequence")
    stiffness: dict[str, Stiffness] = Field(default_factory=dict)
    damping: dict[str, Damping] = Field(default_factory=dict)
    while_held: bool = Field(False, description="undo the stiffness/damping changes "
                                                "when the key is released")
    mode: str | None = Field(None, description="select a control mode (map set)")
    goto: str | None = Field(None, description="go to a state of the state machine")
    reach: ReachSpec | None = None
    grasp: GraspSpec | None = None
    release: str | None = Field(None, description="chain name, or 'all'")
    app: str | None = Field(None, description="an app action: " + ", ".join(META_APP_ACTIONS))
    slowdown: float | None = Field(None, ge=1.0, le=100.0)
    gravity: Gravity | None = Field(None, description="m/s^2")
    friction: Friction | None = Field(None, description="ground friction")
    perturb: Literal["on", "off", "toggle"] | None = None
    description: str = ""

    @field_validator("app")
    @classmethod
    def _app(cls, value):
        if value is not None and value not in META_APP_ACTIONS:
            raise ValueError(f"unknown app action '{value}'; expected one of: "
                             f"{', '.join(META_APP_ACTIONS)}")
        return value

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
