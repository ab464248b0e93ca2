"""World (metres, y up) to screen (pixels, y down), following the character."""

from __future__ import annotations

import math


class Camera:
    def __init__(self, view_height: float, center=(0.0, 0.0), offset: float | None = None):
        self.view_height = view_height  # metres of world from top to bottom of the window
        # metres the view's centre sits above the centre of mass
        self.offset = 0.18 * view_height if offset is None else offset
        self.cx, self.cy = center
        self.width = self.height = 1
        self.scale = 1.0

    def resize(self, width: int, height: int) -> None:
        self.width, self.height = width, height
        self.scale = height / self.view_height

    def target_for(self, com) -> tuple[float, float]:
        """Frame the character a little below the middle so the ground shows."""
        return com[0], com[1] + self.offset

    def follow(self, com, wall_dt: float | None) -> None:
        """Ease toward the character; ``wall_dt=None`` snaps (for screenshots)."""
        tx, ty = self.target_for(com)
        if wall_dt is None:
            self.cx, self.cy = tx, ty
            return
        a = 1.0 - math.exp(-4.0 * wall_dt)
        self.cx += (tx - self.cx) * a
        self.cy += (ty - self.cy) * a

    def to_screen(self, p) -> tuple[float, float]:
        return (self.width / 2 + (p[0] - self.cx) * self.scale,
                self.height / 2 - (p[1] - self.cy) * self.scale)

    def to_world(self, s) -> tuple[float, float]:
        return (self.cx + (s[0] - self.width / 2) / self.scale,
                self.cy - (s[1] - self.height / 2) / self.scale)

    def visible_x(self) -> tuple[float, float]:
        half = self.width / 2 / self.scale
        return self.cx - half, self.cx + half
