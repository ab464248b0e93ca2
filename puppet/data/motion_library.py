"""A motion library (Zordan et al. 2005): windows of clips, each with the features a
figure's state is matched against after an impact, and the clips' channels to follow.

``puppet mocap library FOLDER`` writes one (``puppet.mocap.library``); an interface
names it in ``tracking.reaction.library.file`` (``assets/mocap/NAME.json``). The file is
data: JSON, ``format: puppet-motion-library``, version 1::

    {"format": "puppet-motion-library", "version": 1, "character": "biped",
     "trunk_link": "chest",                       # the link whose angle is 'trunk'
     "rate": 30, "window": 1.0, "hop": 0.1,
     "channels": ["root.x", "root.y", "root.angle", "clearance", "waist", ...],
     "joints": ["waist", "hip_near", ...],        # channels that are joint angles
     "mirror": [["hip_near", "hip_far"], ...],    # pairs a mirrored window swaps
     "clips": [{"name": "cmu-131_01-walk", "mapping": "cmu-131", "frames":
                [[x, y, angle, ...], ...]}],      # the channels at 'rate', in order
     "windows": [{"clip": 0, "start": 12, "mirrored": false,
                  "trunk": 0.05, "spin": -0.3, "com": [1.1, 0.02],
                  "q": [0.01, ...]}]}             # (rad, rad/s, m/s, rad per joint)

A window is ``window`` s of its clip from frame ``start``; its features are the
performed pose's at that frame: the trunk's (chest's) angle in the world and its
turning rate, the centre of mass's velocity and the joint angles (of ``joints``, in
order), mirrored windows with near and far swapped. Loading checks every number is
finite and every index in range: a bad file is one line (``DataError``).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

from puppet.data.errors import DataError

FORMAT = "puppet-motion-library"
MAX_BYTES = 64 * 1024 * 1024  # a library bigger than this is refused unread
MAX_WINDOWS = 100000


@dataclass(frozen=True)
class Window:
    clip: int
    start: int  # the clip frame it begins at
    mirrored: bool
    features: tuple[float, ...]  # trunk, spin, com vx, com vy, then the joints' q


@dataclass(frozen=True)
class MotionLibrary:
    path: str
    character: str
    trunk_link: str  # the link whose angle is the trunk's (its channels: root.angle + trunk)
    rate: float  # frames per second of the clips' channels
    frames: int  # frames a window spans (window * rate + 1)
    channels: tuple[str, ...]
    joints: tuple[str, ...]
    swap: dict  # channel -> its mirror's (near <-> far)
    clips: tuple[tuple[str, tuple[tuple[float, ...], ...]], ...]  # (name, frames)
    windows: tuple[Window, ...]

    @property
    def duration(self) -> float:
        return (self.frames - 1) / self.rate

    def window_name(self, i: int) -> str:
        w = self.windows[i]
        return (f"{self.clips[w.clip][0]} at {w.start / self.rate:.2f} s"
                f"{' (mirrored)' if w.mirrored else ''}")

    def channels_at(self, i: int, t: float) -> dict[str, float]:
        """Window ``i``'s channels ``t`` s into it (linear between frames; held at the
        ends), mirrored if it is."""
        w = self.windows[i]
        frames = self.clips[w.clip][1]
        u = min(max(t, 0.0), self.duration) * self.rate
        k = min(int(u), self.frames - 2) if self.frames > 1 else 0
        f = u - k
        a = frames[w.start + k]
        b = frames[min(w.start + k + 1, len(frames) - 1)]
        names = self.channels
        if w.mirrored:
            names = tuple(self.swap.get(n, n) for n in names)
        return {n: a[j] + (b[j] - a[j]) * f for j, n in enumerate(names)}


def _fail(path, message: str):
    raise DataError(str(path), None, None, message)


def _number(path, where: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
            or abs(v) > 1.0e6:
        _fail(path, f"{where}: expected a finite number (got {str(v)[:40]})")
    return float(v)


def _numbers(path, where: str, v, n: int | None = None) -> tuple[float, ...]:
    if not isinstance(v, list) or (n is not None and len(v) != n):
        _fail(path, f"{where}: expected a list of {n if n is not None else ''} numbers")
    return tuple(_number(path, where, x) for x in v)


def _names(path, where: str, v) -> tuple[str, ...]:
    if not isinstance(v, list) or not all(isinstance(x, str) and 0 < len(x) < 100 for x in v):
        _fail(path, f"{where}: expected a list of names")
    return tuple(v)


_CACHE: dict = {}


def load_library(path) -> MotionLibrary:
    """The library file at ``path`` (kept once read, while the file is unchanged)."""
    path = Path(path)
    try:
        st = path.stat()
        key = (str(path.resolve()), st.st_mtime_ns, st.st_size)
    except OSError as exc:
        _fail(path, f"cannot read: {exc.strerror or exc}")
    if key in _CACHE:
        return _CACHE[key]
    lib = _read(path)
    _CACHE.clear()
    _CACHE[key] = lib
    return lib


def _read(path: Path) -> MotionLibrary:
    try:
        if os.path.getsize(path) > MAX_BYTES:
            _fail(path, f"a motion library larger than {MAX_BYTES // 2**20} MB; refused")
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        _fail(path, f"cannot read: {exc.strerror or exc}")
    except (UnicodeDecodeError, ValueError) as exc:
        _fail(path, f"not a motion library (not JSON: {str(exc)[:80]}); expected one "
                    f"written by 'puppet mocap library FOLDER'")
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        _fail(path, f"not a motion library (no 'format: {FORMAT}'); expected one written "
                    f"by 'puppet mocap library FOLDER'")
    if data.get("version") != 1:
        _fail(path, f"motion library version {str(data.get('version'))[:20]}: this puppet "
                    f"reads version 1")
    try:
        return _parse(path, data)
    except (KeyError, TypeError, IndexError) as exc:
        _fail(path, f"a malformed motion library ({type(exc).__name__}: {str(exc)[:60]})")


def _parse(path: Path, data: dict) -> MotionLibrary:
    character = data["character"]
    if not isinstance(character, str):
        _fail(path, "character: expected a name")
    rate = _number(path, "rate", data["rate"])
    window = _number(path, "window", data["window"])
    if not 1.0 <= rate <= 1000.0:
        _fail(path, f"rate: expected 1..1000 frames per second (got {rate:g})")
    if not 0.0 < window <= 60.0:
        _fail(path, f"window: expected 0..60 s (got {window:g})")
    frames = max(2, round(window * rate) + 1)
    channels = _names(path, "channels", data["channels"])
    joints = _names(path, "joints", data["joints"])
    for name in ("root.x", "root.y", "root.angle", *joints):
        if name not in channels:
            _fail(path, f"channels: no '{name}'")
    swap = {}
    for pair in data.get("mirror", []):
        a, b = _names(path, "mirror", pair)
        if a not in channels or b not in channels:
            _fail(path, f"mirror: '{a}' and '{b}' must both be channels")
        swap[a], swap[b] = b, a
    clips = []
    for i, clip in enumerate(data["clips"]):
        name = clip["name"]
        if not isinstance(name, str):
            _fail(path, f"clips.{i}.name: expected a name")
        if not isinstance(clip["frames"], list) or len(clip["frames"]) > 10**6:
            _fail(path, f"clips.{i}.frames: expected a list of frames")
        rows = tuple(_numbers(path, f"clips.{i}.frames", f, len(channels))
                     for f in clip["frames"])
        clips.append((name, rows))
    windows = []
    if not isinstance(data["windows"], list) or not data["windows"]:
        _fail(path, "windows: expected at least one window")
    if len(data["windows"]) > MAX_WINDOWS:
        _fail(path, f"windows: more than {MAX_WINDOWS}")
    for i, w in enumerate(data["windows"]):
        where = f"windows.{i}"
        clip = w["clip"]
        start = w["start"]
        if isinstance(clip, bool) or not isinstance(clip, int) or not 0 <= clip < len(clips):
            _fail(path, f"{where}.clip: expected a clip's index 0..{len(clips) - 1}")
        if isinstance(start, bool) or not isinstance(start, int) or start < 0 \
                or start + frames > len(clips[clip][1]):
            _fail(path, f"{where}.start: the window runs past its clip's frames")
        features = (_number(path, f"{where}.trunk", w["trunk"]),
                    _number(path, f"{where}.spin", w["spin"]),
                    *_numbers(path, f"{where}.com", w["com"], 2),
                    *_numbers(path, f"{where}.q", w["q"], len(joints)))
        windows.append(Window(clip, start, bool(w.get("mirrored", False)), features))
    trunk = data.get("trunk_link", "chest")
    if not isinstance(trunk, str):
        _fail(path, "trunk_link: expected a link's name")
    return MotionLibrary(str(path), character, trunk, rate, frames, channels, joints, swap,
                         tuple(clips), tuple(windows))


def library_named(name: str, character: str) -> MotionLibrary:
    """The motion library an interface names (``tracking.reaction.library.file``: a
    catalog name, assets/mocap/NAME.json), made for ``character``; a DataError (one
    line) if there is none or it is another figure's."""
    from puppet.data.catalog import find, list_kind

    try:
        path = find("library", name, ())
    except DataError:
        known = ", ".join(n for n, _ in list_kind("library")) or "none"
        raise DataError(name, None, None, f"no motion library named '{name}' in "
                                          f"assets/mocap/ (known: {known}); 'puppet mocap "
                                          f"library FOLDER --out assets/mocap/{name}.json' "
                                          f"writes one") from None
    library = load_library(path)
    if library.character != character:
        raise DataError(library.path, None, None,
                        f"a motion library of {library.character}'s, not {character}'s "
                        f"(puppet mocap library FOLDER --character {character})")
    return library

