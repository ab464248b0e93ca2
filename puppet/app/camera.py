"""World (metres, y up) to screen (pixels, y down), framing the character and its ground.

Horizontally the camera eases after the centre of mass. Vertically it does not follow
the centre of mass (on flat ground the floor would bob with every hop): it holds the
ground the character stands on at a fixed height on screen (``GROUND_AT``, above the
timeline bar) and moves only when the character would leave a dead zone, the window
less its top margin and the bottom strip the timeline bar covers. When the character
and its ground do not both fit (a high jump), the view widens (up to ``MAX_ZOOM_OUT``
times the character's ``view_height``) before the ground is let go; the character
itself is never drawn behind the timeline bar. The window and the video export use the
same camera, so what is exported is what was seen.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

GROUND_AT = 0.22  # the ground's place on screen, as a fraction of the height from the bottom
BOTTOM_RESERVED_PX = 36  # the timeline bar's strip along the bottom (see hud.draw_timeline)
TOP_MARGIN = 0.08  # of the view: room kept above the character
BOTTOM_MARGIN = 0.04  # of the view: room kept between the character and the bar
SIDE_MARGIN = 0.1  # of the view: room kept left and right of the character
MAX_ZOOM_OUT = 2.0  # the view may widen to this many times the character's view_height
LEAD_X = 0.12  # of the view's width: the character sits this much left of the middle,
# in the gap between the HUD's two top panels, with more room ahead (figures go right)
EASE_X = 4.0  # 1/s: how fast the camera catches up horizontally
EASE_Y = 3.0  # 1/s: ... vertically, toward the ground's place
EASE_ZOOM = 2.5  # 1/s


@dataclass(frozen=True)
class Subject:
    """What the camera frames: the centre of mass, the character's bounding box
    (left, bottom, right, top; m) and the height of the ground under it (None over a
    gap or off the scene's ends)."""
    com: tuple[float, float]
    box: tuple[float, float, float, float] | None = None
    ground: float | None = None


def subject_of(session) -> Subject:
    """The camera's view of a session's character: read-only (the shapes' bounding
    boxes as the last step left them), so framing never changes a run."""
    character = session.character
    left = bottom = math.inf
    right = top = -math.inf
    for shapes in character.shapes.values():
        for shape in shapes:
            bb = shape.bb
            left, bottom = min(left, bb.left), min(bottom, bb.bottom)
            right, top = max(right, bb.right), max(top, bb.top)
    box = (left, bottom, right, top) if left < math.inf else None
    scene = session.setup.scene
    ground = None
    if box is not None:  # the highest ground under the character: what it stands on
        for x in (box[0], (box[0] + box[2]) / 2, box[2]):
            y = scene.ground_height(x)
            if y is not None and (ground is None or y > ground):
                ground = y
    return Subject(character.com(), box, ground)


def camera_for(setup) -> Camera:
    """The camera the window and the video export frame a setup with: the character's
    view height, or what the scene's ``view`` asks for (an apparatus in the frame)."""
    view = setup.scene.view
    height = view.height if view is not None and view.height is not None else None
    return Camera(height or setup.character.view_height,
                  fixed_x=view.x if view is not None else None,
                  fixed_y=view.y if view is not None else None)


class Camera:
    def __init__(self, view_height: float, center=(0.0, 0.0), fixed_x: float | None = None,
                 fixed_y: float | None = None):
        self.fixed_x, self.fixed_y = fixed_x, fixed_y  # the scene's view: the middle stays
        self.base_height = view_height  # metres from top to bottom, before any zoom out
        self.view_height = view_height  # metres of world from top to bottom of the window
        self.cx, self.cy = center
        self.width = self.height = 1
        self.scale = 1.0
        self.ground: float | None = None  # the last ground seen under the character
        self.top_px = 0  # a scene's fixed view: the band the HUD's top panels take

    def resize(self, width: int, height: int) -> None:
        self.width, self.height = width, height
        self.scale = self._band() / self.view_height

    def reserve_top(self, px: int | None) -> None:
        """The HUD's top panels reach ``px`` pixels down: a scene's fixed view (an
        apparatus) is framed in the band below them, so that no bar or rung is under a
        panel; a view that follows the character keeps the whole window."""
        px = max(0, min(int(px or 0), self.height // 2)) if self.fixed_y is not None else 0
        if px != self.top_px:
            self.top_px = px
            self.scale = self._band() / self.view_height

    def _band(self) -> int:
        """Pixels of height the view maps its view_height onto."""
        return max(1, self.height - self.top_px)

    def _middle(self) -> float:
        """The screen row of the view's middle."""
        return self.top_px + self._band() / 2

    def _bottom_reserved(self, view_height: float) -> float:
        """Metres of the view's bottom hidden by the timeline bar, plus the margin."""
        px = BOTTOM_RESERVED_PX / self._band()
        return (px + BOTTOM_MARGIN) * view_height

    def target_for(self, subject: Subject) -> tuple[float, float, float]:
        """(x, y, view_height) that frame ``subject``: the ground at GROUND_AT, the
        character inside the dead zone, widening the view if both do not fit."""
        x, y = subject.com
        if self.fixed_x is not None:
            x = self.fixed_x
        else:
            x += LEAD_X * self.width / self._band() * self.view_height
        if subject.ground is not None:
            self.ground = subject.ground
        ground = self.ground
        box = subject.box
        if box is None:  # nothing to frame but the centre of mass
            return x, y + (0.5 - GROUND_AT) * self.base_height, self.base_height
        _, bottom, _, top = box
        vh = self.base_height
        if self.fixed_y is not None:  # the scene's view: held there, as the dead zone lets
            cy = self.fixed_y
        elif ground is not None:  # widen until the ground's place and the top both fit
            need = (top - ground) / (1.0 - GROUND_AT - TOP_MARGIN)
            vh = min(self.base_height * MAX_ZOOM_OUT, max(vh, need))
            cy = ground + (0.5 - GROUND_AT) * vh
        else:
            cy = self.cy
        lo = top + TOP_MARGIN * vh - 0.5 * vh  # lowest centre that shows the top
        hi = bottom - self._bottom_reserved(vh) + 0.5 * vh  # highest that clears the bar
        cy = min(max(cy, lo), hi)  # the bottom wins: never behind the timeline bar
        return x, cy, vh

    def follow(self, subject, wall_dt: float | None) -> None:
        """Ease toward framing ``subject`` (a ``Subject``, or a bare centre of mass);
        ``wall_dt=None`` snaps (for screenshots and the first frame). However it eases,
        the character is kept inside the dead zone."""
        if not isinstance(subject, Subject):
            subject = Subject(tuple(subject))
        tx, ty, tvh = self.target_for(subject)
        if wall_dt is None:
            self.cx, self.cy, self.view_height = tx, ty, tvh
        else:
            self.cx += (tx - self.cx) * (1.0 - math.exp(-EASE_X * wall_dt))
            self.cy += (ty - self.cy) * (1.0 - math.exp(-EASE_Y * wall_dt))
            self.view_height += (tvh - self.view_height) * (1.0 - math.exp(-EASE_ZOOM * wall_dt))
        self.scale = self._band() / self.view_height
        if subject.box is not None and wall_dt is not None:  # the dead zone is hard,
            left, bottom, right, top = subject.box  # whatever the easing
            vh = self.view_height
            lo = top + TOP_MARGIN * vh - 0.5 * vh
            hi = bottom - self._bottom_reserved(vh) + 0.5 * vh
            self.cy = min(max(self.cy, lo), hi)
            half = 0.5 * self.width / self.scale
            side = SIDE_MARGIN * vh
            if right - left + 2 * side < 2 * half:  # a fast slide never leaves the frame
                self.cx = min(max(self.cx, right + side - half), left - side + half)

    def to_screen(self, p) -> tuple[float, float]:
        return (self.width / 2 + (p[0] - self.cx) * self.scale,
                self._middle() - (p[1] - self.cy) * self.scale)

    def to_world(self, s) -> tuple[float, float]:
        return (self.cx + (s[0] - self.width / 2) / self.scale,
                self.cy - (s[1] - self._middle()) / self.scale)

    def visible_x(self) -> tuple[float, float]:
        half = self.width / 2 / self.scale
        return self.cx - half, self.cx + half
