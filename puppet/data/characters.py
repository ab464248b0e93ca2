"""Character files (``characters/*.yaml``): links, joints, PD gains, start pose.

Geometry is given in the character's *model frame*: metres, y up, the character
facing +x, every joint at angle 0. Angles in files are degrees (designers think in
degrees); everything inside puppet is radians.
"""

from __future__ import annotations

from typing import Annotated, ClassVar, Literal

from puppet.data.ranges import (
    Angle,
    Color,
    Corner,
    Damping,
    Elasticity,
    Friction,
    Mass,
    ModelXY,
    Num,
    Size,
    Stiffness,
    Torque,
    parse_step,
)
from puppet.data.validate import Meta, Spec, at, field, validate
from puppet.data.yamlfile import Located, load_file

Vec2 = ModelXY


class BoxShape(Spec, kw_only=True, tag_field="type", tag="box"):
    type: ClassVar[str] = "box"  # the tag: msgspec reads it as the union's 'type:' key
    size: tuple[Size, Size]  # width, height in m
    center: Vec2 = (0.0, 0.0)
    angle: Angle = 0.0  # degrees
    radius: Corner = 0.0  # rounded corners, m


class CircleShape(Spec, kw_only=True, tag_field="type", tag="circle"):
    type: ClassVar[str] = "circle"  # the tag: msgspec reads it as the union's 'type:' key
    radius: Size
    center: Vec2 = (0.0, 0.0)


class SegmentShape(Spec, kw_only=True, tag_field="type", tag="segment"):
    type: ClassVar[str] = "segment"  # the tag: msgspec reads it as the union's 'type:' key
    a: Vec2
    b: Vec2
    radius: Size  # half thickness, m


class PolygonShape(Spec, kw_only=True, tag_field="type", tag="polygon"):
    type: ClassVar[str] = "polygon"  # the tag: msgspec reads it as the union's 'type:' key
    points: Annotated[list[Vec2], Meta(min_length=3, max_length=64)]
    radius: Corner = 0.0


Shape = BoxShape | CircleShape | SegmentShape | PolygonShape  # by their 'type:' key


class LinkSpec(Spec, kw_only=True):
    name: str
    mass: Mass  # kg
    shapes: Annotated[list[Shape], Meta(min_length=1)]
    friction: Friction = 0.8
    elasticity: Elasticity = 0.0
    color: Color = (200, 200, 210)
    # drawing order; far links are drawn darker, behind
    layer: Literal["far", "mid", "near"] = "mid"
    # model frame, m; with inertia, replaces the shapes' mass spread
    center_of_mass: Vec2 | None = None
    # kg*m^2 about the centre of mass; given with center_of_mass
    inertia: Num("inertia") | None = None
    description: str = ""


class PDSpec(Spec, kw_only=True):
    stiffness: Stiffness  # N*m/rad
    damping: Damping  # N*m*s/rad
    max_torque: Torque  # N*m


class JointSpec(Spec, kw_only=True):
    name: str
    parent: str
    child: str
    anchor: Vec2  # pivot, model frame, m
    limits: tuple[Angle, Angle] | None = None  # degrees, child rel. parent
    pd: PDSpec | None = None  # absent: a passive hinge
    description: str = ""


class StartSpec(Spec, kw_only=True):
    angle: Angle = 0.0  # root link angle, degrees
    joints: dict[str, Angle] = field(default_factory=dict)  # degrees
    lift: Num("lift") = 0.0  # m above the scene's start point


class SolverSpec(Spec, kw_only=True):
    """The physics solver's settings while this character plays (absent: the engine's
    defaults, SOLVER_ITERATIONS, COLLISION_SLOP and DEFAULT_DT in
    puppet/physics/simulation.py)."""
    # constraint solver passes per step
    iterations: Annotated[int, Meta(ge=1, le=200)] | None = None
    collision_slop: Num("slop") | None = None  # m of overlap allowed between shapes in contact
    # the simulation step, s: a number (0.0041667) or a fraction ("1/240"), 1/2000..1/30;
    # a session records it in its log's header ('dt'), and a replay takes the header's
    step: float | str | None = None

    def __post_init__(self):
        if self.step is not None:
            try:
                parse_step(self.step)
            except ValueError as exc:
                raise at("step", str(exc)) from None

    @property
    def dt(self) -> float | None:
        """The step in seconds (None: the engine's DEFAULT_DT)."""
        if self.step is None:
            return None
        return parse_step(self.step)


class CharacterSpec(Spec, kw_only=True):
    name: str
    description: str
    notes: str = ""
    view_height: Num("view_height") = 1.0  # m of world shown in the window
    solver: SolverSpec = field(default_factory=SolverSpec)
    links: Annotated[list[LinkSpec], Meta(min_length=1)]
    joints: list[JointSpec] = field(default_factory=list)
    start: StartSpec = field(default_factory=StartSpec)

    @property
    def root(self) -> str:
        return self.links[0].name

    def link(self, name: str) -> LinkSpec:
        return next(link for link in self.links if link.name == name)

    def joint(self, name: str) -> JointSpec:
        return next(joint for joint in self.joints if joint.name == name)

    @property
    def actuated(self) -> list[JointSpec]:
        return [j for j in self.joints if j.pd is not None]


def _check_structure(spec: CharacterSpec, located: Located) -> None:
    """Cross-references the types cannot see: names, tree shape, limits, start pose."""
    names: dict[str, int] = {}
    for i, link in enumerate(spec.links):
        if link.name in names:
            raise located.error(("links", i, "name"), f"duplicate link name '{link.name}'")
        names[link.name] = i
    for i, link in enumerate(spec.links):
        if (link.center_of_mass is None) != (link.inertia is None):
            given, missing = (("center_of_mass", "inertia") if link.inertia is None
                              else ("inertia", "center_of_mass"))
            raise located.error(("links", i, given),
                                f"link '{link.name}' gives {given} without {missing}; "
                                "expected both (explicit mass properties) or neither "
                                "(spread over the shapes)", prefer_key=True)
    has_parent: set[str] = set()
    joint_names: set[str] = set()
    for i, joint in enumerate(spec.joints):
        if joint.name in joint_names:
            raise located.error(("joints", i, "name"), f"duplicate joint name '{joint.name}'")
        joint_names.add(joint.name)
        for end in ("parent", "child"):
            link = getattr(joint, end)
            if link not in names:
                raise located.error(("joints", i, end),
                                    f"unknown link '{link}'; expected one of: {', '.join(names)}")
        if joint.parent == joint.child:
            raise located.error(("joints", i, "child"), "a joint must join two different links")
        if joint.child in has_parent:
            raise located.error(("joints", i, "child"),
                                f"link '{joint.child}' already has a parent joint "
                                f"(links form a tree rooted at '{spec.root}')")
        if joint.child == spec.root:
            raise located.error(("joints", i, "child"),
                                f"'{spec.root}' is the root link (the first one) and "
                                "cannot be a joint's child")
        has_parent.add(joint.child)
        if joint.limits is not None and not joint.limits[0] < joint.limits[1]:
            raise located.error(("joints", i, "limits"),
                                f"limits must be [lower, upper] with lower < upper, "
                                f"got {list(joint.limits)}")
    for i, link in enumerate(spec.links[1:], start=1):
        if link.name not in has_parent:
            raise located.error(("links", i, "name"),
                                f"link '{link.name}' is not attached: no joint has it as child")
    # Tree: every link reaches the root by parents (no cycles).
    parent_of = {j.child: j.parent for j in spec.joints}
    for i, link in enumerate(spec.links):
        seen, cur = set(), link.name
        while cur in parent_of:
            if cur in seen:
                raise located.error(("links", i, "name"), f"joints form a loop at '{cur}'")
            seen.add(cur)
            cur = parent_of[cur]
    for name, value in spec.start.joints.items():
        if name not in joint_names:
            raise located.error(("start", "joints", name),
                                f"unknown joint '{name}'; expected one of: "
                                f"{', '.join(sorted(joint_names))}", prefer_key=True)
        joint = spec.joint(name)
        if joint.limits and not joint.limits[0] <= value <= joint.limits[1]:
            raise located.error(("start", "joints", name),
                                f"start angle {value} deg is outside the joint's limits "
                                f"{list(joint.limits)}")


def parse_character(located: Located) -> CharacterSpec:
    spec = validate(located, CharacterSpec)
    _check_structure(spec, located)
    return spec


def load_character(path) -> CharacterSpec:
    return parse_character(load_file(path))


__all__ = ["CharacterSpec", "LinkSpec", "JointSpec", "PDSpec", "SolverSpec", "load_character",
           "parse_character"]
