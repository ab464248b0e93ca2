"""The ``puppet`` command: play, list, check.

argparse (standard library) rather than a CLI framework: it gives sub-commands,
--help and typed options with no extra dependency.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from puppet import __version__
from puppet.data.errors import DataError
from puppet.data.interfaces import (CHECKPOINT_MAX, CHECKPOINT_MIN, MAX_SLOWDOWN,
                                    MIN_SLOWDOWN)
from puppet.timeline.log import EXISTS

EXIT_DATA_ERROR = 2


def _number_in(what: str, lo: float, hi: float, hint: str):
    """An argparse type: a number lo..hi, else a one-line usage error (exit 2)."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = float("nan")
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"'{text}' is not a {what} from {lo:g} to {hi:g} "
                                              f"({hint})")
        return value
    return parse


_slowdown = _number_in("slowdown", MIN_SLOWDOWN, MAX_SLOWDOWN,
                       "wall s per simulated s: 4 = four times slower, 0.5 = twice as fast")
_checkpoint_every = _number_in("checkpoint interval", CHECKPOINT_MIN, CHECKPOINT_MAX,
                               "simulated seconds, a multiple of 0.5")

# what ``puppet list`` lists; "recording": the window's own logs (recordings/)
KINDS = ("character", "interface", "scene", "script", "log", "recording")


def _play(args: argparse.Namespace) -> int:
    from puppet.data.catalog import find, load_setup
    from puppet.timeline.script import load_script

    if args.record and Path(args.record).exists():  # a log is never silently overwritten
        print(f"puppet play: --record {args.record}: {EXISTS}", file=sys.stderr)
        return EXIT_DATA_ERROR
    script = None
    if args.input and args.headless:
        script = load_script(find("script", args.input))
        if script.interface and Path(script.interface).stem != Path(args.interface).stem:
            print(f"puppet: warning: {args.input} was written for interface "
                  f"'{script.interface}', playing it on '{args.interface}'", file=sys.stderr)
    # A script made for a scene plays there unless --scene says otherwise.
    setup = load_setup(args.interface, args.scene or (script.scene if script else None))
    if args.checkpoint_every is not None:  # the interface's checkpoint_every, overridden
        import dataclasses

        setup = dataclasses.replace(setup, interface=setup.interface.model_copy(
            update={"checkpoint_every": args.checkpoint_every}))
    ghost = None
    if args.ghost:  # a log replaying beside the live character (never touches it)
        from puppet.timeline.ghost import Ghost
        from puppet.timeline.replay import find_log

        ghost = Ghost(find_log(args.ghost))
        for w in ghost.warnings:
            print(w, file=sys.stderr)
    if not args.headless:
        if args.input or args.screenshot or args.frames:
            raise SystemExit("puppet play: --input, --screenshot and --frames need --headless")
        from puppet.app.window import run_window

        return run_window(setup, args.slowdown, record=args.record, no_record=args.no_record,
                          ghost=ghost)
    from puppet.app.headless import run_headless
    from puppet.physics.simulation import DEFAULT_DT
    from puppet.timeline.script import compile_script, run_seconds

    events = compile_script(script, DEFAULT_DT) if script is not None else []
    seconds = run_seconds(script, args.seconds)
    late = sum(1 for step, _ in events if step * DEFAULT_DT > seconds)
    if late:
        print(f"puppet: warning: {late} scripted event(s) come after the run ends at "
              f"{seconds:g} s and never act (set 'seconds:' in the script, or --seconds)",
              file=sys.stderr)
    # --record writes the scripted run as a log (see ``puppet replay``); images too
    session = run_headless(setup, events, seconds, args.screenshot, args.frames, args.fps,
                           slowdown=args.slowdown, record=args.record,
                           description=(script.description or None) if args.input else None,
                           ghost=ghost)
    if args.record:
        print(f"recorded {args.record}")
    c = session.character
    x, y = c.com()
    print(f"t={session.time:.3f}s  com=({x:.3f}, {y:.3f}) m  upright={c.upright()}  "
          f"state={session.sim.state_hash()}")
    if args.screenshot:
        print(f"wrote {args.screenshot}")
    for note in session.blowup_messages:  # the window shows them; here nothing would
        print(f"puppet play: {note}", file=sys.stderr)
    return 0


def _list(args: argparse.Namespace) -> int:
    from puppet.data.catalog import FOLDERS, list_kind

    kinds = [args.kind] if args.kind else list(KINDS)
    for kind in kinds:
        items = list_kind(kind)
        print(f"{kind}s ({FOLDERS[kind][0]}/):")
        if not items:
            print("  (none)")
        width = max((len(n) for n, _ in items), default=0)
        for name, text in items:
            print(f"  {name:<{width}}  {text}")
    return 0


def _check(args: argparse.Namespace) -> int:
    from puppet.checker import check_file

    failed = 0
    for name in args.files:
        try:
            kind = check_file(name)
            if not args.quiet:
                print(f"{name}: ok ({kind})")
        except DataError as exc:
            print(exc, file=sys.stderr)
            failed += 1
    return EXIT_DATA_ERROR if failed else 0


def _bench(args: argparse.Namespace) -> int:
    from puppet.bench import main as bench_main

    return bench_main(quick=args.quick, as_json=args.json, strict=args.strict,
                      only=args.character or None)


def _replay(args: argparse.Namespace) -> int:
    if args.export_motion:  # headless always: a file for animators, no window
        if args.video or args.plot or args.check:
            raise SystemExit("puppet replay: --export-motion goes alone (no --video, --plot "
                             "or --check)")
        from puppet.timeline.motion import export_motion_command

        return export_motion_command(args)
    if args.video or args.plot:
        from puppet.app.export import export_command

        return export_command(args)
    from puppet.timeline.replay import replay_command

    return replay_command(args)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="puppet",
        description="Drive physically simulated planar characters in real time.")
    parser.add_argument("--version", action="version", version=f"puppet {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    play = sub.add_parser("play", help="play an interface in a window (or headless)",
                          description="Open a window and drive the interface's character. "
                                      "With --headless, run a scripted input and write "
                                      "images of what the window shows.")
    play.add_argument("interface", help="interface name (interfaces/NAME.yaml) or path")
    play.add_argument("--scene", help="scene name (assets/scenes/NAME.yaml) or path; "
                                      "default: the interface's")
    play.add_argument("--slowdown", type=_slowdown,
                      help="wall seconds per simulated second (0.1-100; below 1 is faster "
                           "than real time); default: the interface's")
    play.add_argument("--headless", action="store_true", help="no window")
    play.add_argument("--input", metavar="SCRIPT",
                      help="scripted input (assets/scripts/NAME.yaml or path), headless")
    play.add_argument("--seconds", type=float, help="simulated seconds to run headless "
                                                    "(default: the script's, else 5)")
    play.add_argument("--screenshot", metavar="PNG", help="write the final frame")
    play.add_argument("--frames", metavar="DIR", help="write every frame as DIR/frame_N.png")
    play.add_argument("--fps", type=float, default=30.0, help="frame rate for --frames")
    play.add_argument("--record", metavar="PATH",
                      help="write the input log here, a new file: an existing PATH is an "
                           "error (default in a window: recordings/INTERFACE-DATE-TIME.jsonl)")
    play.add_argument("--no-record", action="store_true", help="do not record a log")
    play.add_argument("--checkpoint-every", type=_checkpoint_every, metavar="SECONDS",
                      help="simulated seconds between automatic checkpoints (0.5-600; "
                           "default: the interface's checkpoint_every, else 3)")
    play.add_argument("--ghost", metavar="LOG",
                      help="replay this log as a translucent ghost beside the character, "
                           "in step with its time (the ghost does not touch the live run)")
    play.set_defaults(func=_play)

    replay = sub.add_parser("replay", help="replay input logs (in a window or headless)",
                            description="Replay recorded input logs. Headless prints the "
                                        "final state hash; --check evaluates the log's "
                                        "expectations (exit 1 if one fails).")
    replay.add_argument("logs", nargs="+", metavar="LOG",
                        help="log file(s) (.jsonl), or names (assets/logs/NAME.jsonl, "
                             "else recordings/NAME.jsonl)")
    replay.add_argument("--headless", action="store_true", help="no window, as fast as it goes")
    replay.add_argument("--check", action="store_true",
                        help="evaluate the expectations (header 'expect' or LOG.expect.yaml)")
    replay.add_argument("--until-step", type=int, metavar="N",
                        help="stop at step N (the first time the replay is there "
                             "with no more events for it)")
    replay.add_argument("--as-recorded", action="store_true",
                        help="replay the interface as recorded in the log (its header's "
                             "copy), not today's file")
    replay.add_argument("--allow-truncated", action="store_true",
                        help="replay the valid lines before a corrupt or cut-off one")
    replay.add_argument("--jobs", "-j", type=int, default=1, metavar="N",
                        help="replay several logs in N processes (headless)")
    replay.add_argument("--slowdown", type=_slowdown,
                        help="window and --video: override the recorded slowdown "
                             "(0.1-100; 0.25 watches a replay four times faster)")
    replay.add_argument("--video", metavar="OUT",
                        help="headless: render the replay as the window shows it, HUD "
                             "included, to OUT (.mp4, .mov, .mkv, .avi or .gif)")
    replay.add_argument("--fps", type=float, default=30.0, help="frame rate for --video "
                                                                "and --export-motion "
                                                                "(default 30)")
    replay.add_argument("--size", default="1280x720", metavar="WxH",
                        help="window size drawn for --video (default 1280x720)")
    replay.add_argument("--scale", type=float, default=1.0,
                        help="shrink --video frames by this factor (e.g. 0.5 for a gif)")
    replay.add_argument("--plot", metavar="PNG",
                        help="headless: plot joint targets against actual angles over "
                             "time, one subplot per actuated joint")
    replay.add_argument("--export-motion", metavar="OUT",
                        help="write the performed motion (root position and angle, every "
                             "joint angle, at --fps) to OUT: .bvh (a planar hierarchy named "
                             "after the character's links; Blender imports it) or .csv")
    replay.set_defaults(func=_replay)

    lst = sub.add_parser("list", help="list characters, interfaces, scenes, scripts, logs "
                                      "and your recordings")
    lst.add_argument("kind", nargs="?", choices=KINDS)
    lst.set_defaults(func=_list)

    check = sub.add_parser("check", help="validate data files (exit 0 valid, 2 invalid)")
    check.add_argument("files", nargs="+", metavar="FILE")
    check.add_argument("-q", "--quiet", action="store_true", help="print errors only")
    check.set_defaults(func=_check)

    bench = sub.add_parser("bench", help="measure simulation speed, checkpoints and rewind",
                           description="Headless benchmark of every shipped character: "
                                       "speed with control vs bare pymunk, checkpoint and "
                                       "rewind times, log replay speed; PASS/MISS per "
                                       "target.")
    bench.add_argument("character", nargs="*", help="only these characters (default: all)")
    bench.add_argument("--json", action="store_true", help="machine-readable output")
    bench.add_argument("--quick", action="store_true", help="a short run (for tests)")
    bench.add_argument("--strict", action="store_true", help="exit 1 if a target is missed")
    bench.set_defaults(func=_bench)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return args.func(args)
    except DataError as exc:
        print(f"puppet: {exc}", file=sys.stderr)
        return EXIT_DATA_ERROR
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
