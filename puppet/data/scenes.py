"""Scene files (``assets/scenes/*.yaml``): ground polylines, friction, gravity, start."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, NonNegativeFloat, PositiveFloat

from puppet.data.validate import Spec, validate
from puppet.data.yamlfile import Located, load_file

Vec2 = tuple[float, float]


class GroundSpec(Spec):
    points: list[Vec2] = Field(min_length=2, description="polyline, m, left to right")
    friction: NonNegativeFloat = 0.9
    elasticity: float = Field(0.0, ge=0.0, le=1.0)
    thickness: PositiveFloat = Field(0.02, description="m; the collision radius is half")
    color: tuple[int, int, int] = (92, 84, 74)
    name: str = ""


class MarkerSpec(Spec):
    x: float = Field(description="m")
    label: str
    style: Literal["flag", "line"] = Field(
        "flag", description="flag: a pole with a pennant; line: a board across the ground "
                            "(a take-off or finish line)")


class RulerSpec(Spec):
    """Tick marks along the ground: distances from ``zero`` every ``step`` metres."""
    start: float = Field(alias="from", description="m, first tick")
    to: float = Field(description="m, last tick")
    step: PositiveFloat = Field(description="m between ticks")
    zero: float | None = Field(None, description="m the distances count from "
                                                 "(absent: from)")
    label_every: int = Field(1, ge=0, description="label every n-th tick (0: none)")
    color: tuple[int, int, int] = (250, 250, 245)

    @property
    def origin(self) -> float:
        return self.start if self.zero is None else self.zero

    def ticks(self) -> list[tuple[float, float, bool]]:
        """(x, distance from zero, labelled) for every tick."""
        n = int(round((self.to - self.start) / self.step))
        return [(self.start + k * self.step, self.start + k * self.step - self.origin,
                 self.label_every > 0 and k % self.label_every == 0) for k in range(n + 1)]


class StartSpec(Spec):
    x: float = 0.0
    y: float = 0.0


class SceneSpec(Spec):
    name: str
    description: str
    gravity: Vec2 = (0.0, -9.81)
    ground: list[GroundSpec] = Field(min_length=1)
    start: StartSpec = Field(default_factory=StartSpec)
    markers: list[MarkerSpec] = Field(default_factory=list)
    rulers: list[RulerSpec] = Field(default_factory=list)
    sky: tuple[int, int, int] = (226, 232, 240)

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
