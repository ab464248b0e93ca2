"""What the sub-commands share: exit codes, typed option values, output paths.

Each option type is an argparse ``type``: a bad value is a one-line usage error (exit
2) that says what was expected. Only the standard library and the data layer's bounds
are imported here: the command line starts fast.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from puppet.data.bounds import CHECKPOINT_MAX, CHECKPOINT_MIN, MAX_SLOWDOWN, MIN_SLOWDOWN
from puppet.data.errors import UsageError

EXIT_DATA_ERROR = 2
EXIT_BLOWUP = 3  # a headless run or replay blew up or left the world (each one reported)

IMAGE_EXTS = (".png", ".jpg", ".jpeg", ".bmp", ".tga")  # what pygame.image.save writes
PLOT_EXTS = (".png", ".pdf", ".svg", ".jpg", ".jpeg")  # what matplotlib's Agg writes


def _shown(value) -> str:
    return str(value) if isinstance(value, int) else f"{value:g}"


def in_range(kind, what: str, lo, hi=None, hint: str = "", unit: str = ""):
    """An argparse type: a ``kind`` (int or float) from lo to hi (no hi: lo or more),
    else a one-line usage error (exit 2) that says what was expected."""
    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            value = None
        if value is None or not lo <= value <= (hi if hi is not None else value):
            bound = (f"from {_shown(lo)} to {_shown(hi)}{unit}" if hi is not None
                     else f"of {_shown(lo)} or more")
            raise argparse.ArgumentTypeError(f"'{text}' is not a {what} {bound}"
                                             + (f" ({hint})" if hint else ""))
        return value
    return parse


def number_in(what: str, lo: float, hi: float, hint: str):
    """A number lo..hi (``in_range``)."""
    return in_range(float, what, float(lo), float(hi), hint)


def whole_in(what: str, lo: int, hint: str):
    """A whole number of lo or more (``in_range``)."""
    return in_range(int, what, lo, None, hint)


def size(text: str) -> tuple[int, int]:
    """--size WxH: two whole numbers of pixels, each at least 64."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not WIDTHxHEIGHT in pixels "
                                         f"(e.g. 1280x720)") from None
    if w < 64 or h < 64 or w > 7680 or h > 4320:
        raise argparse.ArgumentTypeError(f"'{text}': each side must be 64 to 7680x4320 pixels")
    return w, h


seconds = number_in("duration", 0.0, 24 * 3600.0, "simulated seconds")
fps = number_in("frame rate", 1.0, 240.0, "frames per second")
scale = number_in("scale", 0.05, 4.0, "0.5 halves the frames")
jobs = whole_in("number of processes", 1, "1 replays in this process")
step = whole_in("step", 0, "simulation steps from the start")
solver_passes = in_range(int, "number of solver passes", 1, 200,
                         "constraint-solver iterations a step, e.g. 36")


def sim_step(text: str) -> float:
    """A simulation step in seconds, written 0.0041667 or 1/240: 1/2000 to 1/30 s."""
    from puppet.timeline.other_physics import parse_step

    try:
        return parse_step(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
def other_physics(args):
    """The ``--solver-passes`` / ``--step`` settings asked for (an ``OtherPhysics``, false
    when neither was given): ``puppet replay``'s and ``puppet playtest``'s."""
    from puppet.timeline.other_physics import OtherPhysics

    return OtherPhysics(iterations=getattr(args, "solver_passes", None),
                        dt=getattr(args, "step", None))


slowdown = number_in("slowdown", MIN_SLOWDOWN, MAX_SLOWDOWN,
                     "wall s per simulated s: 4 = four times slower, 0.5 = twice as fast")
checkpoint_every = number_in("checkpoint interval", CHECKPOINT_MIN, CHECKPOINT_MAX,
                             "simulated seconds, a multiple of 0.5")


def output_file(option: str, path: str, exts) -> Path:
    """An option's output FILE, checked before anything runs: not a folder, and named
    with one of ``exts`` (say what is expected, never write a file of another name)."""
    p = Path(path)
    try:
        if p.is_dir():
            raise UsageError(f"{option} {path}: is a folder; give a file name ending in "
                             f"{' or '.join(exts)}")
        if p.suffix.lower() not in exts:
            got = f"'{p.suffix}'" if p.suffix else "no extension"
            raise UsageError(f"{option} {path}: {got}; give a file name ending in "
                             f"{' or '.join(exts)}")
        if p.parent.exists() and not p.parent.is_dir():
            raise UsageError(f"{option} {path}: {p.parent} is a file, not a folder")
    except OSError as exc:  # a name too long for the file system, a folder not ours...
        from puppet.data.catalog import short_path

        raise UsageError(f"{option} {short_path(path)}: {exc.strerror or exc}") from None
    return p


def output_folder(option: str, path: str) -> Path:
    """An option's output folder: a folder or a new path, not an existing file."""
    p = Path(path)
    try:
        if p.exists() and not p.is_dir():
            raise UsageError(f"{option} {path}: is a file; give a folder (it is created "
                             f"if new)")
    except OSError as exc:
        from puppet.data.catalog import short_path

        raise UsageError(f"{option} {short_path(path)}: {exc.strerror or exc}") from None
    return p
