"""BVH motion capture: read any skeleton, compute its world joint positions, write one.

A BVH file is a joint hierarchy (each joint an ``OFFSET`` from its parent and the
``CHANNELS`` it animates, in order; an ``End Site`` closes a chain) followed by a
``MOTION`` table: one line per frame, one number per channel, in the hierarchy's
order. Nothing is assumed about the skeleton: joint names, how many channels a joint
has (0 to 6, e.g. 6 on the root, 3 on the rest, or 1 for a planar hinge) and their
order (``Zrotation Yrotation Xrotation``, ``Zrotation Xrotation Yrotation``, ...) all
come from the file. Two CMU conversions of the same 31-joint skeleton name their hips
``LeftHip`` and ``LeftUpLeg``; a retargeting maps joints by name, never by position.

Conventions (the common ones, and Blender's importer's):

* rotation channels compose in the order they are listed: ``Zrotation Yrotation
  Xrotation`` with angles z, y, x is ``Rz(z) @ Ry(y) @ Rx(x)``, acting on column
  vectors in the joint's frame; angles are degrees;
* a joint's position in its parent's frame is its ``OFFSET``, rotated by the parent's
  world rotation; position channels (``Xposition`` ...) *replace* the offset on their
  axes, as Blender reads them (files usually give the root ``OFFSET 0 0 0``, where
  either reading agrees);
* lengths are in the file's units (CMU's: 0.056444 m each); ``Clip.world_positions``
  takes a ``scale``.

    clip = read_bvh("assets/mocap/cmu-131_01-walk.bvh")
    clip.frames, clip.frame_time                  # 994, 0.0083333
    knee = clip.angles("LeftKnee")                # (frames, 3) degrees, channel order
    xyz = clip.world_positions(scale=0.056444)    # (frames, joints + end sites, 3) m

A malformed file raises ``DataError``: ``file:line:col: what is wrong, what was
expected``, one line.
"""

from __future__ import annotations

import io
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from puppet.data.errors import DataError

CHANNEL_NAMES = ("Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation")
CMU_UNIT_METRES = 0.056444  # one unit of the CMU BVH conversion (Hahne), in metres
_AXIS = {"X": 0, "Y": 1, "Z": 2}
# A number as BVH files write it (what numpy's reader takes, not Python's "1_000" or "0x1")
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NOT_FINITE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)  # words float() reads
_COUNT = re.compile(r"[0-9]{1,12}")  # a count (ASCII digits; 12 of them are plenty)

# Limits, as a YAML data file has them (puppet.data.yamlfile): a file from anyone cannot
# make puppet read, hold or compute without bound. The shipped clips are 0.7-2 MB, 31
# joints (+5 End Sites), 994-2752 frames; CMU's longest are under 10 MB, rigs with
# fingers about 150 joints.
MAX_BYTES = 32_000_000  # a BVH file's largest size, checked before it is read
MAX_JOINTS = 512  # joints and End Sites
MAX_NAME = 200  # characters of a joint's name
MAX_FRAMES = 1_000_000  # 'Frames: N' (2.3 h at 120 fps)
MAX_VALUES = 8_000_000  # frames x channels: the motion table (64 MB of numbers)
MAX_JOINT_FRAMES = 2_000_000  # frames x joints: the world transforms of every joint
# (96 bytes each: 192 MB at most; playing a clip computes only the joints it reads)


@dataclass
class Joint:
    """One node of the hierarchy. An End Site is a joint with no channels and
    ``end_site=True`` (its name is its parent's plus ``_end``, and ``2``, ``3`` ... if
    that name is taken: by a joint of the file, or by the parent's other End Site)."""

    name: str
    parent: int  # index into Clip.joints, -1 for the root
    offset: np.ndarray  # (3,), in the parent's frame, file units
    channels: tuple[str, ...] = ()
    end_site: bool = False
    first_channel: int = 0  # index of this joint's first column in Clip.motion
    line: int = 0  # where it is declared, for messages

    @property
    def rotation_order(self) -> str:
        """The rotation channels' axes in file order, e.g. ``"ZYX"``."""
        return "".join(c[0] for c in self.channels if c.endswith("rotation"))


@dataclass
class Clip:
    """A BVH clip: ``joints`` (hierarchy order, parents first, End Sites included),
    ``motion`` (frames, channels) as written (degrees and file units), ``frame_time``
    (seconds per frame)."""

    joints: list[Joint]
    motion: np.ndarray
    frame_time: float
    path: str = ""
    _index: dict[str, int] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        self._index = {j.name: i for i, j in enumerate(self.joints)}

    @property
    def frames(self) -> int:
        return self.motion.shape[0]

    @property
    def fps(self) -> float:
        return 1.0 / self.frame_time

    @property
    def names(self) -> list[str]:
        return [j.name for j in self.joints]

    def joint(self, name: str) -> Joint:
        try:
            return self.joints[self._index[name]]
        except KeyError:
            raise KeyError(f"no joint '{name}' in {self.path or 'the clip'}; it has: "
                           f"{', '.join(j.name for j in self.joints if not j.end_site)}") from None

    def index(self, name: str) -> int:
        self.joint(name)
        return self._index[name]

    def channel(self, joint: str, channel: str) -> np.ndarray:
        """One channel of one joint over all frames, e.g. ``("Hips", "Yposition")``."""
        j = self.joint(joint)
        if channel not in j.channels:
            raise KeyError(f"joint '{joint}' has no channel {channel}; it has "
                           f"{' '.join(j.channels) or 'none'}")
        return self.motion[:, j.first_channel + j.channels.index(channel)]

    def angles(self, joint: str) -> np.ndarray:
        """(frames, n) rotation angles in degrees, in the joint's channel order."""
        j = self.joint(joint)
        cols = [j.first_channel + k for k, c in enumerate(j.channels) if c.endswith("rotation")]
        return self.motion[:, cols]

    def local_rotations(self, joint: str | int) -> np.ndarray:
        """(frames, 3, 3) rotation of a joint in its parent's frame."""
        j = self.joints[joint] if isinstance(joint, int) else self.joint(joint)
        out = np.broadcast_to(np.eye(3), (self.frames, 3, 3)).copy()
        for k, c in enumerate(j.channels):
            if c.endswith("rotation"):
                out = out @ axis_rotation(c[0], np.radians(self.motion[:, j.first_channel + k]))
        return out

    def local_translations(self, joint: int) -> np.ndarray:
        """(frames, 3) a joint's position in its parent's frame (file units)."""
        j = self.joints[joint]
        out = np.broadcast_to(j.offset, (self.frames, 3)).copy()
        for k, c in enumerate(j.channels):
            if c.endswith("position"):
                out[:, _AXIS[c[0]]] = self.motion[:, j.first_channel + k]
        return out

    def world_transforms(self) -> tuple[np.ndarray, np.ndarray]:
        """World rotations (frames, joints, 3, 3) and positions (frames, joints, 3)."""
        n, f = len(self.joints), self.frames
        rot = np.empty((f, n, 3, 3))
        pos = np.empty((f, n, 3))
        for i, j in enumerate(self.joints):
            local_r = self.local_rotations(i)
            local_t = self.local_translations(i)
            if j.parent < 0:
                rot[:, i], pos[:, i] = local_r, local_t
            else:
                pr = rot[:, j.parent]
                rot[:, i] = pr @ local_r
                pos[:, i] = pos[:, j.parent] + np.einsum("fab,fb->fa", pr, local_t)
        return rot, pos

    def positions_of(self, names, scale: float = 1.0) -> dict[str, np.ndarray]:
        """(frames, 3) world positions of the named joints and End Sites (the unknown
        names left out), times ``scale``: the forward kinematics of their chains only,
        so that playing a clip through a mapping that reads a few of a big rig's
        joints holds a few joints' transforms, not all of them."""
        wanted = [n for n in names if n in self._index]
        keep: set[int] = set()
        for n in wanted:
            i = self._index[n]
            while i >= 0 and i not in keep:
                keep.add(i)
                i = self.joints[i].parent
        rot: dict[int, np.ndarray] = {}
        pos: dict[int, np.ndarray] = {}
        for i in sorted(keep):  # parents come first in the hierarchy's order
            j = self.joints[i]
            local_r, local_t = self.local_rotations(i), self.local_translations(i)
            if j.parent < 0:
                rot[i], pos[i] = local_r, local_t
            else:
                pr = rot[j.parent]
                rot[i] = pr @ local_r
                pos[i] = pos[j.parent] + np.einsum("fab,fb->fa", pr, local_t)
        return {n: pos[self._index[n]] * scale for n in wanted}

    def world_positions(self, scale: float = 1.0) -> np.ndarray:
        """(frames, joints, 3) every joint's and End Site's world position, times
        ``scale`` (e.g. ``CMU_UNIT_METRES``); columns in ``names`` order."""
        return self.world_transforms()[1] * scale


def axis_rotation(axis: str, angle: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotations by ``angle`` (radians, shape (n,)) about axis X, Y or Z."""
    c, s = np.cos(angle), np.sin(angle)
    one, zero = np.ones_like(c), np.zeros_like(c)
    rows = {"X": ((one, zero, zero), (zero, c, -s), (zero, s, c)),
            "Y": ((c, zero, s), (zero, one, zero), (-s, zero, c)),
            "Z": ((c, -s, zero), (s, c, zero), (zero, zero, one))}[axis]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


# -- reading ----------------------------------------------------------------------------
class _Tokens:
    """The hierarchy's words with their line and column (1-based)."""

    def __init__(self, path: str, lines: list[str]):
        self.path = path
        self.items: list[tuple[str, int, int]] = []
        for n, line in enumerate(lines, 1):
            for m in re.finditer(r"\S+", line):
                self.items.append((m.group(), n, m.start() + 1))
        self.i = 0
        self.last_line = max(1, len(lines))

    def peek(self) -> tuple[str, int, int] | None:
        return self.items[self.i] if self.i < len(self.items) else None

    def next(self, expected: str) -> tuple[str, int, int]:
        tok = self.peek()
        if tok is None:
            raise DataError(self.path, self.last_line, None,
                            f"the hierarchy ends here; expected {expected} (a BVH file has "
                            f"HIERARCHY, ROOT ... {{ }}, then MOTION)")
        self.i += 1
        return tok

    def expect(self, word: str, what: str = "") -> tuple[str, int, int]:
        tok = self.next(f"'{word}'{what}")
        if tok[0] != word:
            self.fail(tok, f"expected '{word}'{what}")
        return tok

    def number(self, what: str) -> float:
        tok = self.next(what)
        value = float(tok[0]) if _NUMBER.fullmatch(tok[0]) else math.nan
        if not math.isfinite(value):
            self.fail(tok, f"expected {what}, a number")
        return value

    def fail(self, tok: tuple[str, int, int], expected: str):
        raise DataError(self.path, tok[1], tok[2], f"'{tok[0]}': {expected}")


def read_bvh(path: str | Path) -> Clip:
    """Read a BVH file; ``DataError`` (one line, with where) if it is malformed."""
    path = str(path)
    try:
        with open(path, "rb") as fh:
            size = os.fstat(fh.fileno()).st_size
            if size > MAX_BYTES:  # said before reading any of it
                raise DataError(path, None, None, _too_big(size))
            raw = fh.read(MAX_BYTES + 1)
    except OSError as exc:
        raise DataError(path, None, None, f"cannot read: {exc.strerror or exc}") from None
    if len(raw) > MAX_BYTES:  # (a file that grew, or no size: a pipe)
        raise DataError(path, None, None, _too_big(len(raw)))
    return parse_bvh(raw.decode("utf-8", errors="replace"), path)


def _too_big(size: int) -> str:
    return (f"the file is {size / 1e6:.1f} MB; a BVH file may be at most "
            f"{MAX_BYTES / 1e6:.0f} MB (cut the clip into shorter takes)")


def parse_bvh(text: str, path: str = "<bvh>") -> Clip:
    """Parse BVH text (see ``read_bvh``). Lines end in LF, CR LF or CR; only those
    count as line ends (a form feed or U+2028 is a space, as in an editor's count)."""
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    m = re.search(r"^[ \t]*MOTION[ \t]*$", text, re.MULTILINE)
    head = text[:m.start()] if m else text
    lines = head.split("\n")
    if lines[-1] == "":  # what follows the last line end
        lines.pop()
    toks = _Tokens(path, lines)
    joints = _hierarchy(toks)
    if m is None:
        raise DataError(path, len(lines) or 1, None,
                        "no MOTION section; expected a line 'MOTION' after the hierarchy, "
                        "then 'Frames: N', 'Frame Time: SECONDS' and the frames")
    line0 = len(lines) + 1  # the MOTION line
    motion, frame_time = _motion(path, text[m.end():], line0, joints)
    return Clip(joints, motion, frame_time, path)


def _hierarchy(toks: _Tokens) -> list[Joint]:
    toks.expect("HIERARCHY", " (the first word of a BVH file)")
    root = toks.expect("ROOT", " and the root joint's name")
    joints: list[Joint] = []
    names: set[str] = set()
    n_channels = 0
    open_: list[int] = []  # the joints whose closing '}' is still to come, innermost last
    kw, parent = root, -1
    while True:  # a loop, not a recursion: any depth of nesting reads
        if kw is not None:
            joint = _joint(toks, joints, names, parent, kw, n_channels)
            n_channels += len(joint.channels)
            if not joint.end_site:
                open_.append(len(joints) - 1)
        if not open_:
            break
        name = joints[open_[-1]].name
        tok = toks.next(f"JOINT, End Site or '}}' to close {name}")
        if tok[0] == "}":
            open_.pop()
            kw = None
        elif tok[0] in ("JOINT", "End"):
            kw, parent = tok, open_[-1]
        else:
            toks.fail(tok, f"expected JOINT, End Site or '}}' to close {name}")
    tok = toks.peek()
    if tok is not None:
        toks.fail(tok, "expected MOTION after the root joint's closing '}' (one ROOT per file)")
    for j in joints:  # an End Site is named after its parent; a joint's name wins
        if j.end_site:
            j.name = base = joints[j.parent].name + "_end"
            k = 1
            while j.name in names:
                k += 1
                j.name = f"{base}{k}"
            names.add(j.name)
    return joints


def _joint(toks: _Tokens, joints: list[Joint], names: set[str], parent: int,
           kw: tuple[str, int, int], first_channel: int) -> Joint:
    """Read a joint's name, OFFSET and CHANNELS (an End Site's OFFSET and '}'); append it."""
    if len(joints) >= MAX_JOINTS:
        toks.fail(kw, f"a BVH file may have at most {MAX_JOINTS} joints and End Sites; "
                      f"this one has more")
    if kw[0] == "End":
        site = toks.expect("Site", " after 'End'")
        name = joints[parent].name + "_end"  # made unique when the hierarchy is read
        line = site[1]
    else:
        name_tok = toks.next(f"the name of the {kw[0].lower()} after {kw[0]}")
        if name_tok[0] == "{":
            toks.fail(name_tok, f"expected the joint's name after {kw[0]}")
        name, line = name_tok[0], kw[1]
        if len(name) > MAX_NAME:
            toks.fail((name[:30] + "...", *name_tok[1:]),
                      f"a joint name of {len(name)} characters; expected at most {MAX_NAME}")
        if name in names:
            toks.fail(name_tok, "a second joint with this name; expected unique joint names")
        names.add(name)
    toks.expect("{", f" to open {name}")
    toks.expect("OFFSET", f" (the first entry of {name}: OFFSET x y z)")
    offset = np.array([toks.number(f"OFFSET {axis} of {name}") for axis in "xyz"])
    joint = Joint(name, parent, offset, (), kw[0] == "End", first_channel, line)
    joints.append(joint)
    if joint.end_site:
        toks.expect("}", " to close the End Site (it has only an OFFSET)")
        return joint
    tok = toks.peek()
    if tok is not None and tok[0] == "CHANNELS":
        toks.next("CHANNELS")
        count_tok = toks.next("the number of channels")
        if not _COUNT.fullmatch(count_tok[0]) or not 0 <= int(count_tok[0]) <= 6:
            toks.fail(count_tok, "expected the number of channels, 0 to 6")
        channels = []
        for k in range(int(count_tok[0])):
            ch = toks.next(f"channel {k + 1} of {count_tok[0]} of {name}")
            if ch[0] not in CHANNEL_NAMES:
                hint = (f" (CHANNELS {count_tok[0]} lists {count_tok[0]} names)"
                        if ch[0] in ("JOINT", "End", "}") else "")
                toks.fail(ch, f"expected a channel name, one of {', '.join(CHANNEL_NAMES)}"
                              f"{hint}")
            if ch[0] in channels:
                toks.fail(ch, f"channel listed twice for {name}; expected each at most once")
            channels.append(ch[0])
        joint.channels = tuple(channels)
    return joint


def _motion(path: str, rest: str, line0: int, joints: list[Joint]) -> tuple[np.ndarray, float]:
    n_ch = sum(len(j.channels) for j in joints)
    lines = rest.split("\n")  # lines[0] is what follows MOTION on its line (empty)
    header: dict[str, tuple[str, int]] = {}
    k = 1
    for key in ("Frames:", "Frame Time:"):
        while k < len(lines) and not lines[k].strip():
            k += 1
        where = line0 + min(k, len(lines) - 1)  # the file's last line if it ends first
        text = lines[k].strip() if k < len(lines) else ""
        if not text.startswith(key):
            raise DataError(path, where, 1, f"'{text[:30]}': expected '{key} "
                            f"{'N' if key == 'Frames:' else 'SECONDS'}' here")
        header[key] = (text[len(key):].strip(), where)
        k += 1
    frames_text, frames_line = header["Frames:"]
    if not _COUNT.fullmatch(frames_text):
        raise DataError(path, frames_line, None, f"Frames: '{frames_text[:30]}': expected a "
                        f"whole number of frames (at most 12 digits)")
    frames = int(frames_text)
    n_nodes = len(joints)
    for what, got, most in (("frames", frames, MAX_FRAMES),
                            ("values (frames x channels)", frames * n_ch, MAX_VALUES),
                            ("joint positions (frames x joints and End Sites)",
                             frames * n_nodes, MAX_JOINT_FRAMES)):
        if got > most:
            raise DataError(path, frames_line, None,
                            f"Frames: {frames} makes {got} {what}; a BVH clip may have at "
                            f"most {most} (cut the clip into shorter takes)")
    ft_text, ft_line = header["Frame Time:"]
    frame_time = float(ft_text) if _NUMBER.fullmatch(ft_text) else math.nan
    if not (math.isfinite(frame_time) and frame_time > 0 and math.isfinite(1 / frame_time)):
        raise DataError(path, ft_line, None, f"Frame Time: '{ft_text[:30]}': expected seconds "
                        f"per frame, a number > 0 (and not so small that frames per second "
                        f"overflow)")
    first = line0 + k  # file line of the first frame
    _count_frames(path, lines[k:], first, frames)  # before a number is read: cheap
    body = "\n".join(lines[k:])
    motion = None
    if n_ch > 0 and body.strip():  # (numpy warns about an empty table)
        try:  # the fast path: numpy's C reader
            motion = np.loadtxt(io.StringIO(body), dtype=float, ndmin=2, comments=None)
        except ValueError:
            motion = None
        if motion is not None and (motion.shape != (frames, n_ch)
                                   or not np.isfinite(motion).all()):
            motion = None
    if motion is None:  # find and name the first bad line
        motion = _motion_slow(path, lines[k:], first, frames, n_ch)
    return motion, frame_time


def _column(line: str, words: list[str], word: str) -> int:
    """1-based column of ``word`` (one of ``line.split()``) in ``line``."""
    at = 0
    for w in words:
        at = line.index(w, at)
        if w is word:
            return at + 1
        at += len(w)
    return 1


def _count_frames(path: str, lines: list[str], first: int, frames: int) -> None:
    """The frame lines (not blank) against 'Frames: N', before any number is read:
    a file with the wrong count is refused without converting its table."""
    count = 0
    for i, line in enumerate(lines):
        if line and not line.isspace():
            count += 1
            if count == frames + 1:
                raise DataError(path, first + i, None,
                                f"more frames than 'Frames: {frames}' says; expected the "
                                f"file to end after frame {frames}")
    if count < frames:
        last = first + len(lines) - 1 if lines else first - 1
        while last >= first and not lines[last - first].strip():
            last -= 1
        raise DataError(path, max(last, first - 1), None,
                        f"the file ends after {count} frames; 'Frames: {frames}' "
                        f"expected {frames}")


def _motion_slow(path: str, lines: list[str], first: int, frames: int, n_ch: int) -> np.ndarray:
    rows = []
    last = first if lines else first - 1  # (the Frame Time line, if the file ends there)
    for i, line in enumerate(lines):
        words = line.split()
        if not words:
            continue
        last = first + i
        if len(rows) == frames:
            raise DataError(path, last, None, f"more frames than 'Frames: {frames}' says; "
                            f"expected the file to end after frame {frames}")
        if len(words) != n_ch:
            raise DataError(path, last, None,
                            f"frame {len(rows) + 1} has {len(words)} values; expected "
                            f"{n_ch}, one per channel of the hierarchy")
        bad = next((w for w in words if not _NUMBER.fullmatch(w)
                    and not _NOT_FINITE.fullmatch(w)), None)  # ('inf abc': the abc)
        if bad is not None:
            raise DataError(path, last, _column(line, words, bad),
                            f"'{bad[:30]}' in frame {len(rows) + 1}: expected a number")
        row = [float(w) for w in words]
        if not all(math.isfinite(v) for v in row):
            raise DataError(path, last, None,
                            f"frame {len(rows) + 1} has a value that is not finite; "
                            f"expected numbers")
        rows.append(row)
    if len(rows) != frames:
        raise DataError(path, last, None, f"the file ends after {len(rows)} frames; "
                        f"'Frames: {frames}' expected {frames}")
    return np.array(rows, dtype=float).reshape(frames, n_ch)


# -- writing ----------------------------------------------------------------------------
@dataclass
class PlanarJoint:
    """A joint of a planar (x right, y up; rotations about z) hierarchy to write:
    ``offset`` (x, y) from the parent joint; ``end`` (x, y), an End Site's offset (a
    joint with no children gets one anyway: Blender draws a bone to it)."""

    name: str
    parent: str | None
    offset: tuple[float, float]
    end: tuple[float, float] | None = None


def write_planar_bvh(path: str | Path, joints: list[PlanarJoint], root_xy: np.ndarray,
                     angles_deg: np.ndarray, frame_time: float, decimals: int = 6) -> None:
    """Write a planar clip: the root moves in the x-y plane (``root_xy``, (frames, 2),
    file units) and every joint turns about z (``angles_deg``, (frames, joints),
    degrees, the root's first: its angle in the world, the others relative to their
    parent). The root has channels ``Xposition Yposition Zposition Zrotation Yrotation
    Xrotation``, the other joints ``Zrotation Yrotation Xrotation``; the out-of-plane
    ones are always zero. Three rotation channels, not one: Blender's importer reads
    all three of a joint that has any (a lone ``Zrotation`` makes it read another
    joint's number) and it reads each line's place, so ``{``, ``OFFSET`` and
    ``CHANNELS`` each have their own line. ``joints`` are parents first; the root's
    offset is 0 (position channels replace the offset, as Blender reads them)."""
    frames = angles_deg.shape[0]
    if angles_deg.shape != (frames, len(joints)) or root_xy.shape != (frames, 2):
        raise ValueError("root_xy must be (frames, 2) and angles_deg (frames, joints)")
    children: dict[str | None, list[PlanarJoint]] = {}
    for j in joints:
        children.setdefault(j.parent, []).append(j)
    roots = children.get(None, [])
    if len(roots) != 1 or roots[0] is not joints[0]:
        raise ValueError("exactly one root, listed first")
    out: list[str] = ["HIERARCHY"]
    order: list[str] = []

    def f(v: float) -> str:
        return f"{v:.{decimals}f}"

    def emit(j: PlanarJoint, depth: int) -> None:
        ind = "\t" * depth
        is_root = j.parent is None
        out.append(f"{ind}{'ROOT' if is_root else 'JOINT'} {j.name}")
        out.append(f"{ind}{{")
        off = (0.0, 0.0) if is_root else j.offset
        out.append(f"{ind}\tOFFSET {f(off[0])} {f(off[1])} {f(0.0)}")
        out.append(f"{ind}\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation "
                   f"Xrotation" if is_root else f"{ind}\tCHANNELS 3 Zrotation Yrotation Xrotation")
        order.append(j.name)
        kids = children.get(j.name, [])
        for kid in kids:
            emit(kid, depth + 1)
        if not kids or j.end is not None:
            end = j.end if j.end is not None else (0.0, 0.05)
            out.extend([f"{ind}\tEnd Site", f"{ind}\t{{",
                    f"{ind}\t\tOFFSET {f(end[0])} {f(end[1])} {f(0.0)}", f"{ind}\t}}"])
        out.append(f"{ind}}}")

    emit(joints[0], 0)
    if len(order) != len(joints):
        raise ValueError("every joint's parent must be a joint listed before it")
    col = {j.name: i for i, j in enumerate(joints)}
    table = np.zeros((frames, 6 + 3 * (len(joints) - 1)))
    table[:, 0:2] = root_xy
    table[:, 3] = angles_deg[:, 0]
    for k, name in enumerate(order[1:]):
        table[:, 6 + 3 * k] = angles_deg[:, col[name]]
    out += ["MOTION", f"Frames: {frames}", f"Frame Time: {frame_time:.7f}"]
    buf = io.StringIO()
    np.savetxt(buf, table, fmt=f"%.{decimals}f", delimiter=" ")
    Path(path).write_text("\n".join(out) + "\n" + buf.getvalue(), encoding="utf-8")
