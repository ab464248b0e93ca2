"""Mocap mapping files (``assets/mappings/*.yaml``): how a source skeleton becomes the
planar figure's channels.

A source (a BVH clip, a VMC or MediaPipe stream) gives named 3-D points: joint
centres, in its own axes and units. A mapping says which axis is up and how long a
unit is, which plane the figure lives in (the performer's direction of travel, their
facing, or a given direction), which point pairs are the figure's segments, and which
channels to make of them: a joint angle (one segment against another), a segment's
angle in the world, the root's forward motion and height, and end effectors relative
to the centre of mass (Ishigaki 2009). A rig with other joint names, units or frame
rate needs another mapping file, never new code. ``puppet.mocap.retarget`` computes
the channels.
"""

from __future__ import annotations

from typing import Annotated, Literal

from puppet.data.errors import DataError, did_you_mean
from puppet.data.ranges import AngleChange, Num
from puppet.data.validate import Meta, Spec, field, validate
from puppet.data.yamlfile import Located, load_file

Axis = Literal["x", "y", "z", "-x", "-y", "-z"]
# Limits besides the YAML file's own (2 MB, 48 levels): what a mapping lists, each
# worked out for every frame of a clip and every datagram of a stream (the shipped ones
# list up to 19 points and 12 segments; a BVH rig has at most 512 joints)
MAX_POINTS = 256
REST = {"forward": 0.0, "up": 90.0, "back": 180.0, "down": -90.0}


class SourceSpec(Spec, kw_only=True):
    up: Axis = "y"  # the source axis that points up (BVH and Unity: y)
    unit: Num("source_unit") = 1.0  # metres per source length unit (CMU BVH: 0.056444, cm: 0.01)
    # the source's axes: right-handed (BVH) or left-handed (Unity, so VMC)
    handedness: Literal["right", "left"] = "right"
    # each axis's length in units, before unit: a picture's normalised landmarks have x in
    # widths and y in heights ([1.3333, 1, 0] for 4:3; 0 drops an axis: a webcam's depth)
    scale: tuple[Num("axis_scale"), Num("axis_scale"), Num("axis_scale")] = (1.0, 1.0, 1.0)


class FacingSpec(Spec, kw_only=True):
    """Two points across the body (the hips), ``left`` and ``right``: the performer
    faces forward of the line between them; or two along it, ``back`` and ``front``
    (an ankle and its toe tip): the performer faces from one to the other (what a
    camera that sees the performer side-on can tell)."""

    left: str | None = None
    right: str | None = None
    back: str | None = None
    front: str | None = None

    def __post_init__(self):
        across, along = (self.left, self.right), (self.back, self.front)
        if not ((None not in across and along == (None, None))
                or (None not in along and across == (None, None))):
            raise ValueError("facing: give left and right (points across the body) or back "
                             "and front (points along the way it faces), one pair")

    @property
    def points(self) -> list[str]:
        return [p for p in (self.left, self.right, self.back, self.front) if p is not None]


class RootSpec(Spec, kw_only=True):
    # the source point the figure's root follows, or several: their mean (the two hip joints: the
    # figure's hip hinge)
    point: str | Annotated[list[str], Meta(max_length=MAX_POINTS)]
    # the floor's height in source units, or 'lowest': the lowest point a clip reaches (a stream: so
    # far)
    floor: Num("world_xy") | Literal["lowest"] = "lowest"

    @property
    def points(self) -> list[str]:
        return [self.point] if isinstance(self.point, str) else list(self.point)


class ClearanceSpec(Spec, kw_only=True):
    """How high the performer's feet are off the floor: the lowest of ``points`` less
    ``standing`` (m: its height with a foot flat on the floor - a toe joint sits some
    centimetres up), never below 0. Channel ``clearance``, m: 0 while a foot is down,
    the height of a jump in flight, so a tracked figure leaves the ground then."""

    points: Annotated[list[str], Meta(min_length=1, max_length=MAX_POINTS)]
    standing: Num("size")  # m above the floor with the foot down


class SegmentSpec(Spec, kw_only=True):
    """A direction from one source point to another; ``rest`` is its direction when
    the figure's joints are all 0 (forward, up, back, down, or degrees, counter-
    clockwise from forward)."""

    start: str = field(name="from")
    to: str
    rest: Literal["forward", "up", "back", "down"] | AngleChange = "down"

    @property
    def rest_degrees(self) -> float:
        return REST[self.rest] if isinstance(self.rest, str) else float(self.rest)


class ChannelSpec(Spec, kw_only=True):
    """A planar angle, degrees: ``segment``'s turn from its rest direction, less
    ``relative_to``'s (a joint angle), or alone (its angle in the world); then
    ``value = angle * scale + offset``. Positive is counter-clockwise with the figure
    facing right, as the figure's joint angles are."""

    segment: str
    relative_to: str | None = None
    offset: AngleChange = 0.0
    scale: Num("coupling") = 1.0


class FilterSpec(Spec, kw_only=True):
    """The 1-euro filter of a live stream's channels (``puppet.mocap.smoothing``): a
    low-pass at ``cutoff`` Hz while the performer is still, rising by ``beta`` Hz per
    deg/s (a centimetre a second counts as a degree) as they move. ``cutoff: 0``: no
    filter. A clip is never filtered."""

    cutoff: Num("cutoff") = 4.0
    beta: Num("cutoff_slope") = 0.02


class MappingSpec(Spec, kw_only=True):
    name: str = ""
    description: str = ""
    notes: str = ""
    # the character whose joints the channels are named for (characters/NAME.yaml): then
    # ``puppet check`` holds every channel to be one of its joints, as play does
    character: str | None = None
    source: SourceSpec = field(default_factory=SourceSpec)
    # the figure's forward direction: 'travel' (where the root goes over a clip), 'facing' (each
    # frame, from the facing points) or [x, y, z] in source axes
    plane: Literal["travel", "facing"] | tuple[Num("input"), Num("input"), Num("input")] = "travel"
    facing: FacingSpec | None = None
    # the figure's size over the performer's (lengths: root motion, effectors)
    size: Num("ratio") = 1.0
    root: RootSpec
    segments: Annotated[dict[str, SegmentSpec], Meta(min_length=1, max_length=MAX_POINTS)]
    channels: Annotated[dict[str, ChannelSpec], Meta(max_length=MAX_POINTS)] = field(
        default_factory=dict)
    # name -> source point: channels NAME.x and NAME.y, m from the centre of mass, in the plane
    effectors: Annotated[dict[str, str], Meta(max_length=MAX_POINTS)] = field(
        default_factory=dict)
    clearance: ClearanceSpec | None = None
    # source point -> weight: the centre of mass (absent: the root point)
    com: Annotated[dict[str, Num("ratio")], Meta(max_length=MAX_POINTS)] = field(
        default_factory=dict)
    # a live stream's filter (a webcam's jitter: more; a suit: less); a clip is not filtered
    filter: FilterSpec = field(default_factory=FilterSpec)

    def __post_init__(self):
        if not isinstance(self.plane, str) and sum(v * v for v in self.plane) == 0:
            raise ValueError("plane: the forward direction [x, y, z] must not be zero")
        for name in self.effectors:
            if f"{name}.x" in self.channels or f"{name}.y" in self.channels:
                raise ValueError(f"effector '{name}' makes channels that 'channels' "
                                 f"defines too")

    def problems(self):
        """(where, message) of each name the mapping uses but does not define, ``where``
        the path of the field in the file (``parse_mapping`` points at its line)."""
        for name, channel in self.channels.items():
            for key, seg in (("segment", channel.segment), ("relative_to", channel.relative_to)):
                if seg is not None and seg not in self.segments:
                    yield (("channels", name, key),
                           f"channel '{name}' names segment '{seg}', which 'segments' does "
                           f"not define{did_you_mean(seg, self.segments)} (known: "
                           f"{', '.join(self.segments)})")
        if isinstance(self.plane, str) and self.facing is None:
            yield (("plane",),
                   f"plane: {self.plane} needs 'facing: {{left: POINT, right: POINT}}' (a "
                   f"stream, and a clip that hardly travels, face the way those points "
                   f"say), or give the plane as [x, y, z]")

    def point_names(self) -> set[str]:
        """Every source point the mapping reads."""
        names = {*self.root.points, *self.effectors.values(), *self.com}
        for seg in self.segments.values():
            names |= {seg.start, seg.to}
        if self.facing is not None:
            names |= set(self.facing.points)
        if self.clearance is not None:
            names |= set(self.clearance.points)
        return names

    def channel_names(self) -> list[str]:
        """The channels it makes, in order: root, angles, effectors."""
        names = ["root.x", "root.y", *self.channels]
        if self.clearance is not None:
            names.append("clearance")
        for name in self.effectors:
            names += [f"{name}.x", f"{name}.y"]
        return names


def _beside(located: Located) -> tuple:
    """The folder of the file ``located`` was read from (a name in it may be a file
    there), or none."""
    from pathlib import Path

    path = Path(located.path)
    return (path.resolve().parent,) if path.is_file() else ()


# channels a mapping may make that are no joint: the root's angle in the world (tracking.root)
ROOT_ANGLE = "root.angle"


def channel_problem(mapping: MappingSpec, joints, character: str,
                    also=()) -> tuple[str | None, str] | None:
    """(the channel, what is wrong) when a channel of ``mapping`` is no joint of the
    character (``joints``: its joint names), or (None, ...) when none of them is one:
    such a channel would drive nothing (a typo, ``knee_naer``, or a mapping written for
    another character). ``also``: other channel names the interface reads (its
    ``tracking.channels``, ``tracking.root.angle``); ``root.angle`` always passes."""
    joints = list(joints)
    allowed = {*joints, ROOT_ANGLE, *also}
    label = f"mapping '{mapping.name}'" if mapping.name else "the mapping"
    if mapping.channels and not any(c in joints for c in mapping.channels):
        return None, (f"no channel of {label} ({', '.join(mapping.channels)}) is a joint "
                      f"of {character} ({', '.join(joints) or 'none'}): it would drive "
                      f"nothing; expected a mapping written for {character}")
    for name in mapping.channels:
        if name not in allowed:
            hint = did_you_mean(name, joints)
            return name, (f"channel '{name}' of {label} is no joint of {character}"
                          f"{hint + ' ' if hint else '; '}expected one of: "
                          f"{', '.join([*joints, ROOT_ANGLE])}")
    return None


def interface_reads(interface) -> set[str]:
    """The channel names an interface reads besides its character's joints: what its
    ``tracking`` renames joints to and its root angle, and every ``channel.NAME``
    input or sensor it names (a map on ``channel.lean``)."""
    import msgspec

    names: set[str] = set()
    tracking = interface.tracking
    if tracking is not None:
        names |= set(tracking.channels.values())
        if tracking.root is not None:
            names.add(tracking.root.angle)

    def walk(value):
        if isinstance(value, str):
            if value.startswith("channel."):
                names.add(value[len("channel."):])
        elif isinstance(value, dict):
            for v in value.values():
                walk(v)
        elif isinstance(value, (list, tuple)):
            for v in value:
                walk(v)

    walk(msgspec.to_builtins(interface))
    return names


def channel_error(path, mapping: MappingSpec, joints, character: str,
                  also=()) -> DataError | None:
    """``channel_problem`` as a DataError at the channel's line in ``path`` (the
    mapping's file), or None."""
    problem = channel_problem(mapping, joints, character, also)
    if problem is None:
        return None
    channel, message = problem
    located = load_file(path)
    return located.error(("channels", channel) if channel else ("channels",), message,
                         prefer_key=True)


def parse_mapping(located: Located) -> MappingSpec:
    """A mapping file's spec; a mapping that names its ``character`` has its channels
    checked against that character's joints."""
    spec = validate(located, MappingSpec)
    for where, message in spec.problems():
        raise located.error(where, message)
    if spec.character is not None:
        from puppet.data.catalog import find  # (the catalog imports widely: here, when needed)
        from puppet.data.characters import parse_character

        try:
            character = parse_character(load_file(find("character", spec.character,
                                                         _beside(located))))
        except DataError as exc:
            raise located.error(("character",), exc.message) from None
        problem = channel_problem(spec, [j.name for j in character.joints], spec.character)
        if problem is not None:
            channel, message = problem
            raise located.error(("channels", channel) if channel else ("channels",),
                                message, prefer_key=True)
    return spec


def load_mapping(path) -> MappingSpec:
    return parse_mapping(load_file(path))
