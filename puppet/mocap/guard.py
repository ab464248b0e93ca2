"""Judging a live stream's samples against what the figure allows, so that no sample,
however absurd, can halt the physics.

A decoder already drops what is not a number, or beyond what its format allows; a
well-formed value can still be absurd for the figure it drives (a VMC bone 100 m long,
a puppet channel of 1e6 degrees, a root 40 m off in one frame), and KD control pulls
the figure toward whatever it is given. So every sample is judged twice more, on the
receiving side, before it becomes an event (what is logged is only what was kept):

* a frame of **points** (VMC, MediaPipe), before the mapping sees it (``PoseGuard``):
  every segment the mapping reads no longer than ``SEGMENT_GROWTH`` times its usual
  length (the median of the frames kept so far) nor than ``SEGMENT_MAX`` metres, and
  the root point moving no faster than ``ROOT_SPEED``: else the whole frame is dropped
  (``bad_pose``), so the mapping's running state (distance travelled, the floor) never
  sees it;
* each **channel** (``ChannelGuard``), against its ``Rule``: a tracked joint's angle
  within the joint's limits widened by ``ANGLE_MARGIN`` (``beyond_range``), the root's
  travel keeping it on the scene's ground and its height within reach of it
  (``off_scene``; the travel counts from the stream's first sample, however late one
  joined it), effectors and clearance within a few of the
  figure's heights (``beyond_range``), a channel a map reads within its map's ``from``
  range widened by its width; and no channel changing faster than its rate
  (``too_fast``: degrees or metres a second, a budget refilled with time and capped at
  ``BURST`` seconds' worth, so a flood of datagrams moves nothing faster than a body
  can).

A dropped channel keeps its last value in the runtime; a frame whose every channel is
dropped is no sample, so a stream of nothing but garbage is tracking lost after
``lost_after`` (the figure goes to the keys). A level the stream keeps for ``REJOIN``
seconds is taken (a sender that re-placed its origin, a performer who came back
elsewhere): the root's travel (``root.x``) and the root point carry on from where they
were (a jump of the origin is no travel), other channels take the new level.

Drops are counted by reason (``GUARD_REASONS``) with what the first of each said; the
HUD and ``puppet mocap listen`` show them beside the decoder's.
"""

from __future__ import annotations

import collections
import math
from dataclasses import dataclass

GUARD_REASONS = ("bad_pose", "beyond_range", "off_scene", "too_fast")
ANGLE_MARGIN = 180.0  # deg a tracked joint's channel may pass its limits by: the tracker clamps
# it; half a turn beyond (or 1e6 degrees) is no pose of that joint, however it was measured
FREE_TURN = 3600.0  # deg: an angle with no limits (the root's, unwrapped) stays within this
TURN_RATE = 3000.0  # deg/s: no limb of a performer turns faster in a plane (a kick, a
# throw's elbow: 1000-2000; the CMU clips' joints: 1200 at the 99.9th percentile, but for
# a limb seen end-on, whose projection flips)
ROOT_SPEED = 15.0  # m/s: no performer's root goes faster (a sprinter: 12)
REACH_SPEED = 30.0  # m/s: a hand or foot relative to the centre of mass
BURST = 1 / 30  # s: the largest change allowed at once is this many seconds' worth (or
# the time since the last sample, after a silence: a 30 Hz sender is never held back)
REJOIN = 0.15  # s: a level the stream keeps this long is taken (a spike lasts a frame or
# two; a limb seen end-on flips its projected angle for good)
SEGMENT_GROWTH = 3.0  # a segment longer than this many times its median: a bad pose
SEGMENT_MAX = 3.0  # m: no performer's segment is longer (before the median is known)
MEDIAN_OF = 31  # kept frames the segments' usual lengths are the median of
SCENE_INSIDE = 0.5  # m: the root's travel keeps it this far inside the ground's ends
REACH = 3.0  # the figure's heights an effector or the clearance may be from the body


@dataclass(frozen=True)
class Rule:
    """What one channel may be: ``lo``..``hi`` (else dropped for ``why``, saying
    ``what``), changing at most ``rate`` a second; ``carry``: a kept jump is no motion
    (the root's travel)."""

    lo: float
    hi: float
    rate: float
    why: str
    what: str
    carry: bool = False


class Tally:
    """Drops by reason, and what the first of each said."""

    def __init__(self):
        self.dropped: collections.Counter = collections.Counter()
        self.first_detail: dict[str, str] = {}
        self.rejoined = 0  # levels taken after REJOIN s

    def drop(self, reason: str, detail: str) -> None:
        assert reason in GUARD_REASONS, reason
        self.dropped[reason] += 1
        self.first_detail.setdefault(reason, detail)

    @property
    def total(self) -> int:
        return sum(self.dropped.values())

    def text(self) -> str:
        """e.g. ``"judged: 5 dropped (3 too_fast, 2 off_scene)"``, or ``""``."""
        if not self.total:
            return ""
        parts = ", ".join(f"{n} {r}" for r, n in sorted(self.dropped.items(),
                                                        key=lambda kv: (-kv[1], kv[0])))
        return f"judged: {self.total} dropped ({parts})"


class _Level:
    """One channel's (or the root point's) running judgement: the last value kept, and
    a budget of change refilled at the rate with time, capped at ``BURST`` s' worth (or
    the gap since the last sample, after a silence)."""

    __slots__ = ("value", "time", "budget", "offset", "pending", "pending_time",
                 "pending_since")

    def __init__(self, value, time: float):
        self.value, self.time = value, time  # the last kept (after the offset)
        self.budget = 0.0  # change allowed now, in the channel's unit
        self.offset = 0.0  # added to what comes (a carried jump)
        self.pending = None  # the last value dropped (as it came)
        self.pending_time = self.pending_since = 0.0  # ... when, and since when steady

    def judge(self, raw, now: float, rate: float, carry: bool, dist) -> tuple[object, str]:
        """(the value to keep, ``"keep"`` or ``"rejoin"``) or (None, ``"drop"``): too fast.
        ``dist(a, b)``: how far apart two values are; ``carry``: a rejoined jump is
        taken into the offset (``raw`` a number)."""
        gap = max(0.0, now - self.time)
        self.time = now
        self.budget = min(self.budget + rate * gap, rate * max(BURST, gap))
        value = raw + self.offset if carry else raw
        change = dist(value, self.value)
        if change <= self.budget:
            self.budget -= change
            self.value = value
            self.pending = None
            return value, "keep"
        steady = (self.pending is not None and
                  dist(raw, self.pending) <= rate * max(BURST, now - self.pending_time))
        if not steady:
            self.pending_since = now  # a new level (or noise): the wait starts again
        self.pending, self.pending_time = raw, now
        if now - self.pending_since < REJOIN:
            return None, "drop"
        if carry:  # the stream kept the new level: take it (a jump of the origin: no motion)
            self.offset += self.value - value
            value = self.value
        self.value, self.budget, self.pending = value, 0.0, None
        return value, "rejoin"


def _apart(a: float, b: float) -> float:
    return abs(a - b)


class ChannelGuard:
    """Judges each channel of a frame by its ``Rule`` (channels without one pass)."""

    def __init__(self, rules: dict[str, Rule], tally: Tally | None = None):
        self.rules = rules
        self.tally = tally or Tally()
        self.levels: dict[str, _Level] = {}

    def judge(self, values: dict[str, float], now: float) -> dict[str, float]:
        out = {}
        tally = self.tally
        for name, value in values.items():
            rule = self.rules.get(name)
            if rule is None:
                out[name] = value
                continue
            level = self.levels.get(name)
            moved = value + level.offset if level is not None else value
            if not rule.lo <= moved <= rule.hi:
                tally.drop(rule.why, f"{name} = {value:.4g}: {rule.what}")
                continue
            if math.isinf(rule.rate):
                out[name] = value
                continue
            if level is None:  # the first sample (a carried channel starts at 0 with it:
                # the root's travel is from where the stream began, however late one joined)
                level = self.levels[name] = _Level(0.0 if rule.carry else value, now)
                if rule.carry:
                    level.offset = -value
                out[name] = level.value
                continue
            before = level.value
            kept, how = level.judge(value, now, rule.rate, rule.carry, _apart)
            if how == "drop":
                tally.drop("too_fast", f"{name} went from {before:.4g} to {moved:.4g} at "
                                       f"once (at most {rule.rate:g} a second)")
                continue
            if how == "rejoin":
                tally.rejoined += 1
            out[name] = kept
        return out


class PoseGuard:
    """Judges a frame of points by the mapping's segments and root (source units
    times the mapping's ``unit``: metres)."""

    def __init__(self, mapping, tally: Tally | None = None):
        self.tally = tally or Tally()
        self.metres = mapping.source.unit
        self.scale = tuple(mapping.source.scale)
        self.segments = {n: (s.start, s.to) for n, s in mapping.segments.items()}
        self.root = list(mapping.root.points)
        self.lengths: dict[str, collections.deque] = {n: collections.deque(maxlen=MEDIAN_OF)
                                                      for n in self.segments}
        self.level: _Level | None = None  # the root point, m

    def judge(self, points: dict, now: float) -> str:
        """``"keep"``, ``"drop"`` (counted) or ``"rejoin"``: keep it, and the mapping
        must forget where the root was (it jumped to a place the stream kept)."""
        if self.scale != (1.0, 1.0, 1.0):
            sx, sy, sz = self.scale
            points = {n: (p[0] * sx, p[1] * sy, p[2] * sz) for n, p in points.items()}
        seen = {}
        for name, (a, b) in self.segments.items():
            if a in points and b in points:
                length = math.dist(points[a], points[b]) * self.metres
                usual = self.lengths[name]
                limit = (SEGMENT_GROWTH * sorted(usual)[len(usual) // 2]
                         if len(usual) >= 5 else SEGMENT_MAX)
                if length > max(limit, 0.05):
                    self.tally.drop("bad_pose", f"segment {name} ({a} to {b}) is "
                                                f"{length:.3g} m long (at most {limit:.3g})")
                    return "drop"
                seen[name] = length
        how = "keep"
        if all(n in points for n in self.root):
            where = tuple(sum(points[n][i] for n in self.root) * self.metres / len(self.root)
                          for i in range(3))
            if self.level is None:
                self.level = _Level(where, now)
            else:
                before = self.level.value
                kept, how = self.level.judge(where, now, ROOT_SPEED, False, math.dist)
                if how == "drop":
                    self.tally.drop("bad_pose", f"the root point moved "
                                                f"{math.dist(where, before):.3g} m at once "
                                                f"(at most {ROOT_SPEED:g} m/s)")
                    return "drop"
                if how == "rejoin":
                    self.tally.rejoined += 1
        for name, length in seen.items():
            self.lengths[name].append(length)
        return how


class Guard:
    """Both judgements, one tally."""

    def __init__(self, rules: dict[str, Rule], mapping=None):
        self.tally = Tally()
        self.channels = ChannelGuard(rules, self.tally)
        self.pose = PoseGuard(mapping, self.tally) if mapping is not None else None

    @property
    def rules(self) -> dict[str, Rule]:
        return self.channels.rules


# -- the rules of a setup ---------------------------------------------------------------
def rules_for(setup, mapping=None) -> dict[str, Rule]:
    """What each channel ``setup`` (a catalog Setup) reads may be: its tracked joints'
    limits, the root within its scene, the mapping's effectors and the clearance within
    reach of the figure, the inputs of maps on ``channel.NAME`` within their ranges."""
    character, interface, scene = setup.character, setup.interface, setup.scene
    tracking = interface.tracking
    rules: dict[str, Rule] = {}
    for name, (lo, hi) in _map_inputs(interface).items():
        width = max(hi - lo, 1e-6)
        rules[name] = Rule(lo - width, hi + width, math.inf, "beyond_range",
                           f"a map reads it over {lo:g}..{hi:g}; expected within "
                           f"{lo - width:g}..{hi + width:g}")
    renames = tracking.channels if tracking is not None else {}
    for joint in character.actuated:
        channel = renames.get(joint.name, joint.name)
        if joint.limits is None:
            rules[channel] = Rule(-FREE_TURN, FREE_TURN, TURN_RATE, "beyond_range",
                                  f"expected an angle within +-{FREE_TURN:g} deg")
        else:
            lo, hi = joint.limits
            rules[channel] = Rule(lo - ANGLE_MARGIN, hi + ANGLE_MARGIN, TURN_RATE,
                                  "beyond_range",
                                  f"{joint.name} turns {lo:g}..{hi:g} deg; expected within "
                                  f"{ANGLE_MARGIN:g} of that")
    xs = [x for g in scene.ground for x, _ in g.points]
    ys = [y for g in scene.ground for _, y in g.points]
    height = _height(character)
    root = tracking.root if tracking is not None and tracking.root is not None else None
    names = ((root.x, root.y, root.angle, root.clearance) if root is not None
             else ("root.x", "root.y", "root.angle", "clearance"))
    back, ahead = min(xs) - scene.start.x + SCENE_INSIDE, max(xs) - scene.start.x - SCENE_INSIDE
    rules[names[0]] = Rule(back, ahead, ROOT_SPEED, "off_scene",
                           f"the root would leave the scene's ground; expected travel within "
                           f"{back:.4g}..{ahead:.4g} m of the start", carry=True)
    top = max(ys) - min(ys) + 2.0 * height
    rules[names[1]] = Rule(-1.0, top, ROOT_SPEED, "off_scene",
                           f"expected a height above the floor of -1..{top:.4g} m")
    rules[names[2]] = Rule(-FREE_TURN, FREE_TURN, TURN_RATE, "beyond_range",
                           f"expected an angle within +-{FREE_TURN:g} deg")
    rules[names[3]] = Rule(0.0, REACH * height, ROOT_SPEED, "beyond_range",
                           f"expected 0..{REACH * height:.3g} m off the floor")
    for effector in (mapping.effectors if mapping is not None else {}):
        for axis in ("x", "y"):
            rules[f"{effector}.{axis}"] = Rule(
                -REACH * height, REACH * height, REACH_SPEED, "beyond_range",
                f"expected within {REACH * height:.3g} m of the centre of mass")
    return rules


def guard_for(setup, mapping=None) -> Guard:
    """The guard of a live source playing on ``setup`` through ``mapping`` (a
    MappingSpec, or None for a stream of channels)."""
    return Guard(rules_for(setup, mapping), mapping)


def _height(character) -> float:
    """m: the figure's extent over its joints' hinges and links' centres of mass (at
    least 0.2): about its height (the biped: 1.56 of 1.75)."""
    ys = [j.anchor[1] for j in character.joints] + [link.center_of_mass[1]
                                                    for link in character.links
                                                    if link.center_of_mass is not None]
    xs = [j.anchor[0] for j in character.joints]
    span = max(max(ys) - min(ys), max(xs) - min(xs)) if ys and xs else 0.0
    return max(0.2, span)


def _map_inputs(interface) -> dict[str, tuple[float, float]]:
    """channel name -> the widest ``from`` range of the maps reading ``channel.NAME``
    (grid maps: 0..1)."""
    import msgspec

    out: dict[str, tuple[float, float]] = {}

    def note(name, lo, hi):
        if isinstance(name, str) and name.startswith("channel."):
            key = name[len("channel."):]
            lo, hi = min(lo, hi), max(lo, hi)
            old = out.get(key)
            out[key] = (lo, hi) if old is None else (min(old[0], lo), max(old[1], hi))

    def walk(value):
        if isinstance(value, dict):
            if "input" in value and "to" in value:
                lo, hi = value.get("from", (0.0, 1.0))
                note(value["input"], float(lo), float(hi))
            if "grid" in value:
                note(value.get("x"), 0.0, 1.0)
                note(value.get("y"), 0.0, 1.0)
            for v in value.values():
                walk(v)
        elif isinstance(value, (list, tuple)):
            for v in value:
                walk(v)

    walk(msgspec.to_builtins(interface))
    return out
