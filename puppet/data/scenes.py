"""Scene files (``assets/scenes/*.yaml``): ground polylines, friction, gravity, start,
and props: named static or dynamic bodies (bars, rungs, a rope's links, a wall) with
named grasp points and grasp segments that a hand or foot can hold."""

from __future__ import annotations

from typing import Annotated, Literal

from puppet.data.ranges import Color, Elasticity, Friction, Gravity, Num, WorldXY
from puppet.data.validate import Meta, Spec, field, validate
from puppet.data.yamlfile import Located, load_file

Vec2 = WorldXY


class GroundSpec(Spec, kw_only=True):
    points: Annotated[list[Vec2], Meta(min_length=2)]  # polyline, m, left to right
    friction: Friction = 0.9
    elasticity: Elasticity = 0.0
    thickness: Num("thickness") = 0.02  # m; the collision radius is half
    color: Color = (92, 84, 74)
    name: str = ""


class MarkerSpec(Spec, kw_only=True):
    x: Num("world_xy")  # m
    label: str
    # flag: a pole with a pennant; line: a board across the ground (a take-off or finish line)
    style: Literal["flag", "line"] = "flag"


class RulerSpec(Spec, kw_only=True):
    """Tick marks along the ground: distances from ``zero`` every ``step`` metres."""
    start: Num("world_xy") = field(name="from")  # m, first tick
    to: Num("world_xy")  # m, last tick
    step: Num("size")  # m between ticks
    zero: Num("world_xy") | None = None  # m the distances count from (absent: from)
    label_every: Annotated[int, Meta(ge=0)] = 1  # label every n-th tick (0: none)
    color: Color = (250, 250, 245)

    @property
    def origin(self) -> float:
        return self.start if self.zero is None else self.zero

    def ticks(self) -> list[tuple[float, float, bool]]:
        """(x, distance from zero, labelled) for every tick."""
        n = int(round((self.to - self.start) / self.step))
        return [(self.start + k * self.step, self.start + k * self.step - self.origin,
                 self.label_every > 0 and k % self.label_every == 0) for k in range(n + 1)]


class PropShapeSpec(Spec, kw_only=True):
    """One collision shape of a prop, in the prop's own frame (m): a segment (a bar, a
    rung, a wall's face) with a radius, or a circle."""

    segment: tuple[Vec2, Vec2] | None = None
    circle: Vec2 | None = None  # centre, m
    radius: Num("size") = 0.02  # m
    friction: Friction = 0.9
    collide: bool = True  # the character collides with it (a bar held only by grasps need not)

    def __post_init__(self):
        if (self.segment is None) == (self.circle is None):
            raise ValueError("a prop shape needs exactly one of 'segment' or 'circle'")
        if self.segment is not None and self.segment[0] == self.segment[1]:
            raise ValueError("a segment needs two distinct ends")


class PropSpec(Spec, kw_only=True):
    """A named body in the scene that characters may touch and grasp. ``static`` props
    never move; ``dynamic`` ones have a mass and may hang from a ``pivot`` (a pin to the
    world or to another prop: a pendulum bar, a rope made of links)."""

    body: Literal["static", "dynamic"] = "static"
    position: Vec2  # the prop's origin in the world, m
    angle: Num("angle") = 0.0  # deg
    mass: Num("mass") | None = None  # kg (dynamic props)
    shapes: list[PropShapeSpec] = field(default_factory=list)
    # name -> point in the prop's frame, m; their order is the order reaches count in (next,
    # previous)
    grasp_points: dict[str, Vec2] = field(default_factory=dict)
    # segments any point of which may be held
    grasp_segments: list[tuple[Vec2, Vec2]] = field(default_factory=list)
    pivot: Vec2 | None = None  # world point the prop hangs from, m
    pivot_to: str | None = None  # the prop the pivot pins it to (default: the world)
    color: Color = (120, 110, 100)
    description: str = ""

    def __post_init__(self):
        if self.body == "dynamic" and self.mass is None:
            raise ValueError("a dynamic prop needs a 'mass' (kg)")
        if self.body == "static" and (self.mass is not None or self.pivot is not None):
            raise ValueError("a static prop has no 'mass' or 'pivot'; make it "
                             "'body: dynamic' to let it move")
        if self.pivot_to is not None and self.pivot is None:
            raise ValueError("'pivot_to' needs a 'pivot' point")
        if self.body == "dynamic" and not self.shapes:
            raise ValueError("a dynamic prop needs at least one shape (for its inertia)")


class StartSpec(Spec, kw_only=True):
    x: Num("world_xy") = 0.0
    y: Num("world_xy") = 0.0


class ViewSpec(Spec, kw_only=True):
    """How the window frames this scene, where following the character alone would not
    show what it holds (an apparatus above it): the view's height, and where its middle
    stays (the camera then moves only as far as keeps the character in the frame)."""
    # m of world from the window's top to its bottom (default: the character's view_height)
    height: Num("view_height") | None = None
    # m: the view's middle across (default: it follows the centre of mass)
    x: Num("world_xy") | None = None
    # m: the height of the view's middle (default: the ground's place on screen)
    y: Num("world_xy") | None = None


class SceneSpec(Spec, kw_only=True):
    name: str
    description: str
    gravity: Gravity = (0.0, -9.81)
    ground: Annotated[list[GroundSpec], Meta(min_length=1)]
    start: StartSpec = field(default_factory=StartSpec)
    markers: list[MarkerSpec] = field(default_factory=list)
    props: dict[str, PropSpec] = field(default_factory=dict)  # name -> a static or dynamic body
    rulers: list[RulerSpec] = field(default_factory=list)
    sky: Color = (226, 232, 240)
    # how the window frames the scene (default: it follows the character)
    view: ViewSpec | None = None

    def ground_height(self, x: float) -> float | None:
        """Highest ground y directly under x, or None off the ends."""
        best = None
        for ground in self.ground:
            for (x0, y0), (x1, y1) in zip(ground.points, ground.points[1:]):
                lo, hi = min(x0, x1), max(x0, x1)
                if lo <= x <= hi and x1 != x0:
                    y = y0 + (y1 - y0) * (x - x0) / (x1 - x0)
                    best = y if best is None else max(best, y)
        return best


def parse_scene(located: Located) -> SceneSpec:
    spec = validate(located, SceneSpec)
    for i, ground in enumerate(spec.ground):
        for k, (a, b) in enumerate(zip(ground.points, ground.points[1:])):
            if a == b:
                raise located.error(("ground", i, "points", k + 1),
                                    "repeated point: a ground segment needs two distinct ends")
    names = list(spec.props)
    for i, (name, prop) in enumerate(spec.props.items()):
        if prop.pivot_to is not None and prop.pivot_to not in names[:i]:
            from puppet.data.interface_refs import unknown

            if prop.pivot_to in names:
                message = (f"prop '{prop.pivot_to}' is listed after '{name}'; a prop can "
                           "only be pinned to a prop listed before it (move it up)")
            else:
                message = unknown("prop", prop.pivot_to, names[:i], " listed before it")
            raise located.error(("props", name, "pivot_to"), message)
    for i, ruler in enumerate(spec.rulers):
        if not ruler.to > ruler.start:
            raise located.error(("rulers", i, "to"),
                                f"a ruler runs left to right: 'to' ({ruler.to:g}) must be "
                                f"greater than 'from' ({ruler.start:g})")
        count = (ruler.to - ruler.start) / ruler.step
        if count > 2000:
            raise located.error(("rulers", i, "step"),
                                f"{count:.0f} ticks from {ruler.start:g} to {ruler.to:g} m; "
                                "expected at most 2000 (a larger step)")
        if abs(count - round(count)) > 1e-6:
            raise located.error(("rulers", i, "step"),
                                f"step {ruler.step:g} m does not divide the ruler's "
                                f"{ruler.to - ruler.start:g} m; expected a whole number "
                                "of steps from 'from' to 'to'")
    return spec


def load_scene(path) -> SceneSpec:
    return parse_scene(load_file(path))
