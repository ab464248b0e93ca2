"""Scene files (``assets/scenes/*.yaml``): ground polylines, friction, gravity, start."""

from __future__ import annotations

from pydantic import Field

from puppet.data.ranges import Color, Elasticity, Friction, Gravity, Num, WorldXY
from puppet.data.validate import Spec, validate
from puppet.data.yamlfile import Located, load_file

Vec2 = WorldXY


class GroundSpec(Spec):
    points: list[Vec2] = Field(min_length=2, description="polyline, m, left to right")
    friction: Friction = 0.9
    elasticity: Elasticity = 0.0
    thickness: Num("thickness") = Field(0.02, description="m; the collision radius is half")
    color: Color = (92, 84, 74)
    name: str = ""


class MarkerSpec(Spec):
    x: Num("world_xy") = Field(description="m")
    label: str


class StartSpec(Spec):
    x: Num("world_xy") = 0.0
    y: Num("world_xy") = 0.0


class SceneSpec(Spec):
    name: str
    description: str
    gravity: Gravity = (0.0, -9.81)
    ground: list[GroundSpec] = Field(min_length=1)
    start: StartSpec = Field(default_factory=StartSpec)
    markers: list[MarkerSpec] = Field(default_factory=list)
    sky: Color = (226, 232, 240)

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
    return spec


def load_scene(path) -> SceneSpec:
    return parse_scene(load_file(path))
