"""Retargeting: a performer's named 3-D points become the planar figure's channels.

What the mapping file says (``puppet.data.mappings``) is done in four moves, the same
for a whole clip (vectorised over its frames) and for a live stream (a frame at a time,
``Retargeter.channels``), which a test holds equal:

1. the source's axes: a left-handed frame (Unity's, so VMC's) is mirrored into a right-
   handed one, ``up`` is the source's up axis;
2. the plane: its forward direction is horizontal - where the root travels over the
   clip, the way the performer faces (from two points across the hips), or given - and
   each point becomes (forward, up) in metres (``unit``, then ``size``);
3. angles: a segment's direction in the plane less its rest direction; a joint angle is
   one segment's less another's. Angles are continuous, never jumping by a turn (an
   ankle or an elbow seen near +-180 wobbles across without flipping): each frame's
   is the one of its whole turns nearest the last frame's, starting in -180..180. An
   angle in the world (``root.angle``) is unwrapped for good (a somersault reaches
   360); a joint angle goes back a turn if it passes ``TURN_LIMIT`` (225: past the
   wobble at +-180, and short of the turns a running sum would drift by where a limb
   seen nearly end-on spins in the projection); a segment seen end-on (projected to
   less than a fifth of its length) holds its last good angle;
4. the root: ``root.x`` is the forward distance travelled since the first frame (the
   sum of each frame's move along that frame's forward, so a performer who turns
   still walks the figure forward), ``root.y`` the root point's height above the floor;
   effectors are points relative to the centre of mass (``com`` weights).

Channel values are degrees and metres, as interface files write them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from puppet.data.errors import DataError
from puppet.data.mappings import MappingSpec, load_mapping  # noqa: F401 (re-exported)

END_ON = 0.2  # a segment projected to less than this fraction of its length is end-on
TURN_LIMIT = 225.0  # deg: a joint angle further than this from its rest goes a turn back
MIN_TRAVEL = 0.05  # m: less root travel than this over a clip, and 'travel' uses facing


def _axes(mapping: MappingSpec) -> tuple[np.ndarray, np.ndarray]:
    """(mirror, up): a diagonal that makes the source's frame right-handed (and each
    axis as long as the others: ``source.scale``), and the up unit vector (in the
    mirrored frame)."""
    axis = mapping.source.up
    index = "xyz".index(axis[-1])
    up = np.zeros(3)
    up[index] = -1.0 if axis.startswith("-") else 1.0
    mirror = np.ones(3)
    if mapping.source.handedness == "left":
        mirror[(index + 1) % 3] = -1.0  # flip an axis that is not up: now right-handed
    return mirror * np.asarray(mapping.source.scale, float), up


def _horizontal(v: np.ndarray, up: np.ndarray) -> np.ndarray:
    """``v`` (..., 3) with its up component removed."""
    return v - (v @ up)[..., None] * up


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return v / n


@dataclass
class RetargetedClip:
    """A clip's channels, one value per clip frame; ``at(t)`` interpolates."""

    times: np.ndarray  # (frames,) s
    channels: dict[str, np.ndarray]  # name -> (frames,)

    @property
    def duration(self) -> float:
        return float(self.times[-1]) if len(self.times) else 0.0

    def at(self, t: float) -> dict[str, float]:
        """The channels at time ``t`` (s from the clip's start), linearly between
        frames; before the start the first frame, after the end the last. Channels
        with no value yet (NaN: never seen) are left out."""
        times = self.times
        if t <= times[0]:
            i, w = 0, 0.0
        elif t >= times[-1]:
            i, w = len(times) - 1, 0.0
        else:
            i = int(np.searchsorted(times, t, side="right")) - 1
            w = (t - times[i]) / (times[i + 1] - times[i])
        out = {}
        for name, values in self.channels.items():
            a = values[i]
            v = a if w == 0.0 else a + (values[i + 1] - a) * w
            if v == v:
                out[name] = float(v)
        return out


class Retargeter:
    """A mapping made ready: ``clip`` for a whole take, ``channels`` for a stream."""

    def __init__(self, mapping: MappingSpec, source_name: str = "<source>"):
        self.mapping = mapping
        self.source_name = source_name  # for errors: the clip's file
        self.mirror, self.up = _axes(mapping)
        self.point_names = mapping.point_names()
        self.metres = mapping.source.unit * mapping.size
        plane = mapping.plane
        self.fixed_forward = None
        if not isinstance(plane, str):
            f = _horizontal(np.asarray(plane, float) * self.mirror, self.up)
            if np.linalg.norm(f) < 1e-9:
                raise DataError(mapping.name or "<mapping>", None, None,
                                "plane: the forward direction is vertical; expected a "
                                "horizontal direction")
            self.fixed_forward = _unit(f)
        self.reset()

    def reset(self) -> None:
        """Forget the stream so far (a new take starts from root.x = 0)."""
        self._last: dict[str, float] = {}  # channel -> last value (continuity, holds)
        self._root_prev: np.ndarray | None = None
        self._root_x = 0.0
        self._floor: float | None = None
        self._forward: np.ndarray | None = self.fixed_forward

    def rebase(self) -> None:
        """The stream's root jumped to a place it kept (a sender that re-placed its
        origin): the travel goes on from here (no jump in ``root.x``) and the floor is
        found again (``floor: lowest``)."""
        self._root_prev = None
        self._floor = None

    # -- the math, on (frames, 3) arrays -----------------------------------------------
    def _points(self, points: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
        return {n: np.asarray(p, float) * self.mirror for n, p in points.items()}

    def _root(self, pts) -> np.ndarray | None:
        names = self.mapping.root.points
        if any(n not in pts for n in names):
            return None
        return sum(pts[n] for n in names) / len(names)

    def _facing(self, pts) -> np.ndarray | None:
        face = self.mapping.facing
        if face is None or any(n not in pts for n in face.points):
            return None
        if face.back is not None:  # along the way it faces (a foot seen side-on)
            return _unit(_horizontal(pts[face.front] - pts[face.back], self.up))
        across = pts[face.left] - pts[face.right]
        return _unit(_horizontal(np.cross(across, self.up), self.up))

    def _angles(self, pts, forward: np.ndarray) -> dict[str, np.ndarray]:
        """Each segment's angle (deg, less its rest) per frame; NaN where end-on or
        missing."""
        up = self.up
        out = {}
        for name, seg in self.mapping.segments.items():
            if seg.start not in pts or seg.to not in pts:
                continue
            d = pts[seg.to] - pts[seg.start]
            x = np.sum(d * forward, axis=-1)
            y = d @ up
            length = np.linalg.norm(d, axis=-1)
            with np.errstate(invalid="ignore"):
                seen = np.hypot(x, y) >= END_ON * length
            angle = np.degrees(np.arctan2(y, x)) - seg.rest_degrees
            out[name] = np.where(seen & (length > 0), angle, np.nan)
        return out

    def _joint_values(self, angles) -> dict[str, tuple[np.ndarray, object]]:
        """channel -> (its angle before scale and offset, its spec)."""
        out = {}
        for name, ch in self.mapping.channels.items():
            if ch.segment not in angles:
                continue
            a = angles[ch.segment]
            if ch.relative_to is not None:
                if ch.relative_to not in angles:
                    continue
                a = a - angles[ch.relative_to]
            out[name] = (a, ch)
        return out

    def _effectors(self, pts, forward) -> dict[str, np.ndarray]:
        m = self.mapping
        if m.com:
            present = [(n, w) for n, w in m.com.items() if n in pts]
            if not present:
                return {}
            total = sum(w for _, w in present)
            com = sum(pts[n] * w for n, w in present) / total
        else:
            com = self._root(pts)
            if com is None:
                return {}
        out = {}
        for name, point in m.effectors.items():
            if point in pts:
                d = pts[point] - com
                out[f"{name}.x"] = np.sum(d * forward, axis=-1) * self.metres
                out[f"{name}.y"] = (d @ self.up) * self.metres
        return out

    # -- a whole clip ------------------------------------------------------------------
    def clip(self, points: Mapping[str, np.ndarray], frame_time: float,
             source_names: Sequence[str] | None = None) -> RetargetedClip:
        """Every channel over a take: ``points`` name -> (frames, 3), source units;
        ``source_names``: every point the source has (for the error when the mapping
        reads one it has not; default, those of ``points``)."""
        pts = self._points(points)
        missing = sorted(self.point_names - set(pts))
        if missing:
            raise DataError(self.source_name, None, None, self.missing_message(
                missing, list(points) if source_names is None else list(source_names)))
        m, up = self.mapping, self.up
        root = self._root(pts)
        frames = len(root)
        if frames == 0:
            raise DataError(self.source_name, None, None,
                            "the clip has no frames; expected at least one to play")
        if self.fixed_forward is not None:
            forward = np.broadcast_to(self.fixed_forward, (frames, 3))
        elif m.plane == "facing":
            forward = _filled(self._facing(pts))
        else:  # travel: where the root goes, first frame to last
            travel = _horizontal(root[-1] - root[0], up)
            if np.linalg.norm(travel) * m.source.unit >= MIN_TRAVEL:
                forward = np.broadcast_to(_unit(travel), (frames, 3))
            else:
                face = self._facing(pts)
                if face is None:
                    raise DataError(m.name or "<mapping>", None, None,
                                    "plane: travel, but the root hardly moves over the "
                                    "clip; expected 'facing' points or a given plane")
                forward = np.broadcast_to(_filled(face)[0], (frames, 3))
        channels: dict[str, np.ndarray] = {}
        move = np.zeros(frames)
        move[1:] = np.sum((root[1:] - root[:-1]) * forward[1:], axis=-1)
        channels["root.x"] = np.cumsum(move) * self.metres
        floor = self._clip_floor(pts)
        channels["root.y"] = (root @ up - floor) * self.metres
        for name, (a, ch) in self._joint_values(self._angles(pts, forward)).items():
            channels[name] = _continuous(_held(_wrap(a)), ch.relative_to is None) \
                * ch.scale + ch.offset
        channels.update(self._effectors(pts, forward))
        clear = self._clearance(pts, floor)
        if clear is not None:
            channels["clearance"] = clear
        times = np.arange(frames) * frame_time
        return RetargetedClip(times, channels)

    def missing_message(self, missing: Sequence[str], source_names: Sequence[str]) -> str:
        """Which points the mapping reads that the source has not (each with a
        did-you-mean among the source's), and what the source has."""
        import difflib  # only for a mistake

        where = f"mapping '{self.mapping.name}'" if self.mapping.name else "the mapping"
        shown = []
        for name in missing:
            close = difflib.get_close_matches(name, source_names, n=1, cutoff=0.8)
            shown.append(f"{name} (did you mean {close[0]}?)" if close else name)
        cut = 8
        listed = ", ".join(shown[:cut]) + (f", ... ({len(missing)} in all)"
                                          if len(missing) > cut else "")
        names = list(source_names)
        has = ", ".join(names[:12]) + (", ..." if len(names) > 12 else "")
        return (f"no point named {listed}, which {where} reads; the source has "
                f"{len(names)} point{'s' if len(names) != 1 else ''}: {has or 'none'}")

    def _clearance(self, pts, floor: float):
        """The feet's height off the floor (m, 0 with a foot down), or None."""
        spec = self.mapping.clearance
        if spec is None or any(n not in pts for n in spec.points):
            return None
        low = np.min(np.stack([pts[n] @ self.up for n in spec.points]), axis=0)
        unit, size = self.mapping.source.unit, self.mapping.size
        return np.maximum(0.0, (low - floor) * unit - spec.standing) * size

    def _clip_floor(self, pts) -> float:
        floor = self.mapping.root.floor
        if floor != "lowest":
            return float(floor)
        return float(min(np.min(p @ self.up) for p in pts.values()))

    # -- a stream, a frame at a time ---------------------------------------------------
    def channels(self, points: Mapping[str, Sequence[float]]) -> dict[str, float]:
        """One frame of a stream: ``points`` name -> (x, y, z), source units. Channels
        whose points are missing are left out; a segment seen end-on holds its last
        value."""
        pts = {n: v[None, :] for n, v in self._points(
            {n: points[n] for n in self.point_names if n in points}).items()}
        m, up = self.mapping, self.up
        if self.fixed_forward is None:
            face = self._facing(pts)
            if face is not None and np.all(np.isfinite(face)):
                if m.plane == "facing" or self._forward is None:
                    self._forward = face[0]
        forward = self._forward
        out: dict[str, float] = {}
        if forward is None:
            return out
        forward = forward[None, :]
        last = self._last
        root = self._root(pts)
        if root is not None:
            root = root[0]
            if self._root_prev is not None:
                self._root_x += float((root - self._root_prev) @ forward[0]) * self.metres
            self._root_prev = root
            lowest = min(float(p[0] @ up) for p in pts.values())
            if m.root.floor == "lowest":
                self._floor = lowest if self._floor is None else min(self._floor, lowest)
                floor = self._floor
            else:
                floor = float(m.root.floor)
            out["root.x"] = self._root_x
            out["root.y"] = (float(root @ up) - floor) * self.metres
            clear = self._clearance(pts, floor)
            if clear is not None:
                out["clearance"] = float(clear[0])
        for name, (a, ch) in self._joint_values(self._angles(pts, forward)).items():
            value = float(a[0])
            prev = last.get(name)
            if value != value:  # end-on: hold
                if prev is None:
                    continue
                out[name] = prev * ch.scale + ch.offset
                continue
            value = _continued(prev, _wrap(value), ch.relative_to is None)
            last[name] = value
            out[name] = value * ch.scale + ch.offset
        for name, v in self._effectors(pts, forward).items():
            out[name] = float(v[0])
        return out


def _wrap(a):
    """Degrees into [-180, 180) (an array or a number)."""
    return (a + 180.0) % 360.0 - 180.0


def _continued(prev: float | None, wrapped: float, world: bool) -> float:
    """``wrapped`` (in -180..180) by the whole turns that put it nearest ``prev``; a
    joint angle (not ``world``) that would pass +-``TURN_LIMIT`` goes a turn back."""
    if prev is None:
        return wrapped
    value = wrapped + 360.0 * round((prev - wrapped) / 360.0)
    if not world and abs(value) > TURN_LIMIT:
        value -= math.copysign(360.0, value)
    return value


def _continuous(a: np.ndarray, world: bool) -> np.ndarray:
    """A clip's angles (in -180..180, NaN before the first seen) made continuous as
    ``_continued`` does frame by frame; unchanged (the same array) where no frame's
    turns by more than half a turn from the last."""
    step = np.abs(np.diff(a[~np.isnan(a)]))
    if not (step > 180.0).any():
        return a
    out = a.copy()
    prev = None
    for i, v in enumerate(a.tolist()):
        if v != v:
            continue
        prev = out[i] = _continued(prev, v, world)
    return out


def _filled(forward: np.ndarray) -> np.ndarray:
    """(frames, 3) directions with each unusable one (the hips stacked: NaN) taken
    from the last good frame before it (the first good one for a start without)."""
    good = np.all(np.isfinite(forward), axis=-1)
    if good.all():
        return forward
    if not good.any():
        raise DataError("<clip>", None, None, "the facing points never give a "
                                              "direction; expected hips side by side")
    index = np.where(good, np.arange(len(forward)), -1)
    np.maximum.accumulate(index, out=index)
    index[index < 0] = int(np.argmax(good))
    return forward[index]


def _held(a: np.ndarray) -> np.ndarray:
    """NaNs replaced by the last good value before them (leading NaNs stay)."""
    good = ~np.isnan(a)
    if good.all() or not good.any():
        return a
    index = np.where(good, np.arange(len(a)), -1)
    np.maximum.accumulate(index, out=index)
    out = np.where(index >= 0, a[np.maximum(index, 0)], np.nan)
    return out


def clip_points(clip, names) -> dict[str, np.ndarray]:
    """A BVH clip's world positions (source units) of the named joints and end sites."""
    return clip.positions_of(names)


def retarget_clip(clip, mapping: MappingSpec, name: str = "<clip>") -> RetargetedClip:
    """A BVH clip's channels through ``mapping`` (``name``: the clip's file, for errors)."""
    rt = Retargeter(mapping, name)
    return rt.clip(clip_points(clip, rt.point_names), clip.frame_time,
                   [j.name for j in clip.joints if not j.end_site])


