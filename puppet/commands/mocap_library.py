"""``puppet mocap library FOLDER``: index a folder of BVH clips into a motion library
(Zordan et al. 2005) that ``tracking.reaction.library`` searches after an impact. Only
argparse at the top: the command line starts fast."""

from __future__ import annotations

import argparse
import sys


def _positive(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected seconds, got {text!r}") from None
    if not 0.01 <= v <= 60.0:
        raise argparse.ArgumentTypeError(f"expected 0.01..60 s, got {text}")
    return v


def register(msub) -> None:
    """``library`` under ``puppet mocap`` (``msub``: its sub-parsers)."""
    parser = msub.add_parser(
        "library", help="index a folder of BVH clips into a motion library",
        description="Index every BVH clip of a folder (any humanoid rig: each clip's "
                    "mapping is the shipped one naming its joints, or the one its "
                    "recognised rig gives) into a motion library: windows with the "
                    "features a figure's state is matched against after an impact "
                    "(trunk angle and turning rate, centre-of-mass velocity, joint "
                    "angles). An interface names it in tracking.reaction.library.file.")
    parser.add_argument("folder", help="a folder of .bvh clips")
    parser.add_argument("--out", "-o", metavar="FILE",
                        help="the library file to write (default FOLDER/library.json; "
                             "an interface finds assets/mocap/NAME.json by NAME)")
    parser.add_argument("--character", default="biped", metavar="NAME",
                        help="the figure it is for (default biped)")
    parser.add_argument("--window", type=_positive, default=1.0, metavar="S",
                        help="seconds a window lasts (default 1)")
    parser.add_argument("--hop", type=_positive, default=0.1, metavar="S",
                        help="seconds between windows' starts (default 0.1)")
    parser.add_argument("--no-mirror", action="store_true",
                        help="leave out the mirrored windows (near and far swapped)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from puppet.data.errors import UsageError
    from puppet.mocap.library import index_folder, write_library

    notes: list[str] = []
    library = index_folder(args.folder, args.character, window=args.window, hop=args.hop,
                           mirror=not args.no_mirror, notes=notes)
    for note in notes:
        print(f"puppet mocap library: warning: {note}", file=sys.stderr)
    out = Path(args.out) if args.out else Path(args.folder) / "library.json"
    if out.suffix != ".json":
        raise UsageError(f"--out {out}: expected a .json file")
    try:
        write_library(library, out)
    except OSError as exc:
        raise UsageError(f"cannot write {out}: {exc.strerror or exc}") from None
    clips = ", ".join(c["name"] for c in library["clips"])
    print(f"wrote {out}: {len(library['windows'])} windows of {args.window:g} s from "
          f"{len(library['clips'])} clip(s) ({clips})")
    return 0
