"""The ``puppet`` command: play, list, check.

argparse (standard library) rather than a CLI framework: it gives sub-commands,
--help and typed options with no extra dependency.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from puppet import __version__
from puppet.data.errors import DataError, UsageError
from puppet.data.bounds import CHECKPOINT_MAX, CHECKPOINT_MIN, MAX_SLOWDOWN, MIN_SLOWDOWN

EXIT_DATA_ERROR = 2
EXIT_BLOWUP = 3  # a headless run or replay blew up or left the world (each one reported)


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


def _whole_in(what: str, lo: int, hint: str):
    """An argparse type: a whole number >= lo, else a one-line usage error (exit 2)."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = lo - 1
        if value < lo:
            raise argparse.ArgumentTypeError(f"'{text}' is not a {what} of {lo} or more "
                                              f"({hint})")
        return value
    return parse


def _size(text: str) -> tuple[int, int]:
    """--size WxH: two whole numbers of pixels, each at least 64."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not WIDTHxHEIGHT in pixels "
                                          f"(e.g. 1280x720)") from None
    if w < 64 or h < 64 or w > 7680 or h > 4320:
        raise argparse.ArgumentTypeError(f"'{text}': each side must be 64 to 7680x4320 pixels")
    return w, h


_seconds = _number_in("duration", 0.0, 24 * 3600.0, "simulated seconds")
_fps = _number_in("frame rate", 1.0, 240.0, "frames per second")
_scale = _number_in("scale", 0.05, 4.0, "0.5 halves the frames")
_jobs = _whole_in("number of processes", 1, "1 replays in this process")
_step = _whole_in("step", 0, "simulation steps from the start")
_slowdown = _number_in("slowdown", MIN_SLOWDOWN, MAX_SLOWDOWN,
                       "wall s per simulated s: 4 = four times slower, 0.5 = twice as fast")
_checkpoint_every = _number_in("checkpoint interval", CHECKPOINT_MIN, CHECKPOINT_MAX,
                               "simulated seconds, a multiple of 0.5")

# what ``puppet list`` lists; "recording": the window's own logs (recordings/)
KINDS = ("character", "interface", "scene", "script", "log", "recording")


def _kind(text: str) -> str:
    """``puppet list KIND``: a kind as the headings print it (interfaces) or singular."""
    word = text.strip().lower()
    return word[:-1] if word.endswith("s") and word[:-1] in KINDS else word


IMAGE_EXTS = (".png", ".jpg", ".jpeg", ".bmp", ".tga")  # what pygame.image.save writes
PLOT_EXTS = (".png", ".pdf", ".svg", ".jpg", ".jpeg")  # what matplotlib's Agg writes


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


def _play(args: argparse.Namespace) -> int:
    from puppet.data.catalog import find, load_setup
    from puppet.timeline.log import EXISTS
    from puppet.timeline.script import load_script

    if args.input and Path(args.input).suffix.lower() == ".jsonl":  # not a YAML error
        raise UsageError(f"--input {args.input}: a .jsonl file is a recorded log, not a "
                         f"script (assets/scripts/NAME.yaml); play it back with: "
                         f"puppet replay {args.input}")
    if not args.headless and (args.input or args.screenshot or args.frames):
        raise UsageError("--input, --screenshot and --frames need --headless")
    if args.record and Path(args.record).exists():  # a log is never silently overwritten
        raise UsageError(f"--record {args.record}: {EXISTS}")
    if args.screenshot:
        output_file("--screenshot", args.screenshot, IMAGE_EXTS)
    if args.frames:
        output_folder("--frames", args.frames)
    script = None
    if args.input and args.headless:
        script_path = find("script", args.input)
        script = load_script(script_path)
        if script.scene and not args.scene:  # a name in a file: the catalog or beside it
            script.scene = str(find("scene", script.scene, (script_path.resolve().parent,)))
    # A script made for a scene plays there unless --scene says otherwise.
    setup = load_setup(args.interface, args.scene or (script.scene if script else None))
    if script is not None and script.interface and Path(script.interface).stem not in (
            Path(args.interface).stem, setup.interface.name):  # (a copy keeps its name)
        print(f"puppet play: warning: {args.input} was written for interface "
              f"'{script.interface}', playing it on '{args.interface}'", file=sys.stderr)
    if script is not None:  # a drag or push must name a link of this character
        from puppet.timeline.script import check_links

        check_links(script_path, script, [link.name for link in setup.character.links])
    for w in setup.warnings:  # valid but probably not meant (two maps on one joint)
        print(w, file=sys.stderr)
    if args.checkpoint_every is not None:  # the interface's checkpoint_every, overridden
        import dataclasses

        setup = dataclasses.replace(setup, interface=setup.interface.model_copy(
            update={"checkpoint_every": args.checkpoint_every}))
    from puppet.mocap.commands import live_play

    live = live_play(args, setup)  # --mocap: a live take (window or headless)
    if live is not None:
        return live
    ghost = None
    if args.ghost:  # a log replaying beside the live character (never touches it)
        from puppet.timeline.ghost import Ghost
        from puppet.timeline.replay import find_log

        ghost = Ghost(find_log(args.ghost))
        for w in ghost.warnings:
            print(w, file=sys.stderr)
    clip = None
    if args.mocap:  # a recorded clip plays in sim time, through the interface's mapping
        from puppet.mocap.clip_source import ClipSource
        from puppet.mocap.clips import choose_mapping, open_clip

        mapping, mapping_path, note = choose_mapping(args.mocap, args.mapping, setup.interface,
                                                     setup.interface_path, setup.character)
        if note:  # not the interface's: a shipped one that fits the clip, or its rig's
            print(f"puppet play: {note}", file=sys.stderr)
        if setup.interface.tracking is not None:
            from puppet.data.tracking import mapping_problem

            problem = mapping_problem(setup.interface.tracking, mapping,
                                      [j.name for j in setup.character.actuated])
            if problem:
                raise UsageError(f"--mocap: {problem} ({mapping_path})")
        clip = ClipSource(open_clip(args.mocap, mapping), name=Path(args.mocap).stem,
                          loop=args.loop, drop=args.mocap_drop)
        from puppet.data.catalog import find
        from puppet.mocap.bvh import read_bvh
        from puppet.mocap.info import mapping_unit_note

        note = mapping_unit_note(read_bvh(find("clip", args.mocap)), mapping, mapping_path)
        if note:  # a clip in metres read as centimetres plays a 10 cm performer
            print(f"puppet play: warning: {note}", file=sys.stderr)
    elif args.mapping or args.loop or args.mocap_drop:
        raise UsageError("--mapping, --loop and --mocap-drop go with --mocap (the clip they "
                         "are for)")
    if (clip is not None and args.loop and args.headless and args.seconds is None
            and (script is None or script.seconds is None)):  # it would play once, silently
        raise UsageError("--loop headless needs --seconds S: a looping clip has no end, "
                         f"and a headless run without --seconds lasts the clip once "
                         f"({clip.clip.duration:.2f} s)")
    if not args.headless:
        from puppet.app.window import run_window

        return run_window(setup, args.slowdown, record=args.record, no_record=args.no_record,
                          ghost=ghost, overlay=args.overlay == "com",
                          note=setup.warnings[0] if setup.warnings else "",
                          sources=[clip] if clip is not None else ())
    from puppet.app.headless import run_headless
    from puppet.physics.simulation import DEFAULT_DT
    from puppet.timeline.script import compile_script, late_note, run_seconds

    events = compile_script(script, DEFAULT_DT) if script is not None else []
    seconds = run_seconds(script, args.seconds)
    if clip is not None:
        if args.seconds is None and (script is None or script.seconds is None):
            seconds = clip.clip.duration  # a clip's run lasts the clip
        events = sorted(events + clip.events(DEFAULT_DT, seconds), key=lambda e: e[0])
    late = (late_note(script, seconds, DEFAULT_DT, args.seconds is not None, clip is not None)
            if script else None)
    if late:  # entries as written, and how long the script runs
        print(f"puppet play: warning: {late}", file=sys.stderr)
    # --record writes the scripted run as a log (see ``puppet replay``); images too
    session = run_headless(setup, events, seconds, args.screenshot, args.frames, args.fps,
                           slowdown=args.slowdown, record=args.record,
                           description=(script.description or None) if args.input else None,
                           ghost=ghost, overlay=args.overlay == "com")
    if args.record:
        print(f"recorded {args.record}")
    print(end_line(session))
    if args.screenshot:
        print(f"wrote {args.screenshot}")
    if args.frames:
        print(f"wrote {session.frames_written} frames to {args.frames}")
    return blowup_exit(session)


def end_line(session) -> str:
    """How a headless play ended: time, centre of mass, upright, the state's hash."""
    c = session.character
    x, y = c.com()
    return (f"t={session.time:.3f}s  com=({x:.3f}, {y:.3f}) m  upright={c.upright()}  "
            f"state={session.sim.state_hash()}")


def blowup_exit(session, prog: str = "puppet play") -> int:
    """A headless play's exit code: each blow-up's message on stderr (the window shows
    them; here nothing would), then EXIT_BLOWUP if there was one, else 0. A clip run
    and a live take (puppet.mocap.commands.live_play) end through here."""
    for note in session.blowup_messages:
        print(f"{prog}: {note}", file=sys.stderr)
    return EXIT_BLOWUP if session.blowups else 0


def _mocap_info(args: argparse.Namespace) -> int:
    from puppet.mocap.info import describe

    notes: list[str] = []
    print(describe(args.clip, args.mapping, notes))
    for note in notes:  # e.g. a performer 0.10 m tall: a unit wrong
        print(f"puppet mocap info: warning: {note}", file=sys.stderr)
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
    from puppet.checker import check_file, find_target

    failed = 0
    for name in args.files:
        try:
            warnings: list[str] = []
            # a path as given, or a name: then the file's path, the same in the ok line
            path = find_target(name)  # as in its errors and warnings (checker._shown)
            kind = check_file(path, warnings)
            for w in warnings:
                print(w, file=sys.stderr)
            if not args.quiet:  # a name says which file it was
                print(f"{name if path == Path(name) else path}: ok ({kind})")
        except DataError as exc:
            print(f"puppet check: {exc}", file=sys.stderr)
            failed += 1
    return EXIT_DATA_ERROR if failed else 0


def _bench(args: argparse.Namespace) -> int:
    from puppet.bench import main as bench_main

    return bench_main(quick=args.quick, as_json=args.json, strict=args.strict, cpu=args.cpu,
                      only=args.character or None)


def _replay(args: argparse.Namespace) -> int:
    if args.export_motion:  # headless always: a file for animators, no window
        if args.video or args.plot or args.check:
            raise UsageError("--export-motion goes alone (no --video, --plot or --check)")
        if len(args.logs) != 1:
            raise UsageError("--export-motion takes one log")
        from puppet.timeline.motion import FORMATS, export_motion_command

        output_file("--export-motion", args.export_motion, FORMATS)  # before the replay

        return export_motion_command(args)
    if args.video:
        from puppet.app.export import GIF_EXTS, VIDEO_EXTS

        output_file("--video", args.video, tuple(sorted(VIDEO_EXTS | GIF_EXTS)))
    if args.plot:
        output_file("--plot", args.plot, PLOT_EXTS)
    if args.video or args.plot:
        from puppet.app.export import export_command

        return export_command(args)
    from puppet.timeline.report import replay_command

    # What the imports made (modules, classes, functions) lives as long as the process:
    # out of the collector's way, a full collection during the replay no longer walks
    # it (gc.freeze: about 15 ms of a short headless replay's ~140).
    import gc

    gc.freeze()
    return replay_command(args)


class Parser(argparse.ArgumentParser):
    """argparse's parser, its mistakes in one line (README, Errors): ``puppet play:
    argument --seconds: '-1' is not ... (puppet play --help)``, exit 2, with no usage
    block above it. Sub-command parsers are made of the same class (add_subparsers)."""

    def error(self, message: str):
        self.exit(EXIT_DATA_ERROR, f"{self.prog}: {message} ({self.prog} --help)\n")

    def parse_known_args(self, args=None, namespace=None):
        # The innermost parser's prog ("puppet mocap send") ends up in the namespace: a
        # sub-command's parser writes it after its parent did (argparse copies the
        # sub-namespace over), so messages name the command that was run.
        namespace = argparse.Namespace() if namespace is None else namespace
        namespace.command_prog = self.prog
        return super().parse_known_args(args, namespace)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
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
    play.add_argument("--seconds", type=_seconds, help="simulated seconds to run headless "
                                                    "(default: the script's, else 5)")
    play.add_argument("--screenshot", metavar="PNG",
                      help="headless: write the final frame to this image file (.png, .jpg, "
                           ".bmp or .tga)")
    play.add_argument("--frames", metavar="DIR",
                      help="headless: write every frame as DIR/frame_N.png (DIR is created)")
    play.add_argument("--fps", type=_fps, default=30.0,
                      help="frame rate for --frames (1-240, default 30)")
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
    play.add_argument("--mocap", metavar="CLIP|udp://HOST:PORT",
                      help="drive the figure with a motion-capture clip (.bvh, or a name: "
                           "assets/mocap/NAME.bvh), played in sim time through the "
                           "interface's mapping; headless runs last the clip's length "
                           "unless --seconds says otherwise. Or a live OSC stream, "
                           "udp://127.0.0.1:39539 (see --mocap-format), paced in real "
                           "time and recorded")
    play.add_argument("--loop", action="store_true",
                      help="play the --mocap clip over and over (headless: needs --seconds, "
                           "a looping clip has no end)")
    from puppet.mocap.commands import drop_option

    play.add_argument("--mocap-drop", type=drop_option, metavar="FROM:UNTIL",
                      help="no sample of the --mocap clip from FROM to UNTIL s: the "
                           "stream lost, to try what the interface does then")
    play.add_argument("--mapping", metavar="MAPPING",
                      help="the mocap mapping (assets/mappings/NAME.yaml or a path); "
                           "default: the interface's tracking.mapping")
    play.add_argument("--overlay", choices=["com"],
                      help="com: start with the balance overlay on (centre of mass, its "
                           "ground point, the support between the outermost ground "
                           "contacts, the extrapolated centre of mass); F4 toggles it")
    from puppet.mocap.commands import add_play_options, add_subcommands

    add_play_options(play)  # --mocap-format (--mocap udp://...: a live stream)
    play.set_defaults(func=_play)

    mocap = sub.add_parser("mocap", help="motion capture: what a clip holds; stream a clip "
                                         "live, watch a stream",
                           description="Motion-capture clips and streams: a clip's "
                                       "skeleton and angles; send a BVH clip over OSC as "
                                       "a live source would; listen and print what "
                                       "arrives.")
    mocap_sub = mocap.add_subparsers(dest="mocap_command", metavar="WHAT", required=True)
    info = mocap_sub.add_parser("info", help="a clip's skeleton, frame rate, length and "
                                             "the planar angles it would give")
    info.add_argument("clip", help="a BVH file, or a name: assets/mocap/NAME.bvh")
    info.add_argument("--mapping", help="the mapping (assets/mappings/NAME.yaml or a path); "
                                        "default: the first whose points the clip has "
                                        "(by name)")
    info.set_defaults(func=_mocap_info)
    add_subcommands(mocap_sub)  # puppet mocap send / listen (live OSC)
    from puppet.mocap.rig_command import register as register_rig_mapping

    register_rig_mapping(mocap_sub)  # puppet mocap mapping CLIP: a recognised rig's mapping

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
    replay.add_argument("--until-step", type=_step, metavar="N",
                        help="stop at step N (the first time the replay is there "
                             "with no more events for it); past the log's end the run "
                             "goes on without input to N, and a note on stderr says so")
    replay.add_argument("--as-recorded", action="store_true",
                        help="replay the interface as recorded in the log (its header's "
                             "copy), not today's file")
    replay.add_argument("--allow-truncated", action="store_true",
                        help="replay the valid lines before a corrupt or cut-off one")
    replay.add_argument("--jobs", "-j", type=_jobs, default=1, metavar="N",
                        help="replay several logs in N processes (headless)")
    replay.add_argument("--slowdown", type=_slowdown,
                        help="window and --video: override the recorded slowdown "
                             "(0.1-100; 0.25 watches a replay four times faster)")
    replay.add_argument("--video", metavar="OUT",
                        help="headless: render the replay as the window shows it, HUD "
                             "included, to OUT (.mp4, .mov, .mkv, .avi or .gif); the last "
                             "frame is held 1 s more, with the replay's verdict, so that a "
                             "player or a looping gif does not end on the last move")
    replay.add_argument("--fps", type=_fps, default=30.0,
                        help="frame rate for --video (1-240, at most 50 for a gif; default 30) "
                             "and --export-motion")
    replay.add_argument("--size", type=_size, default=(1280, 720), metavar="WxH",
                        help="window size drawn for --video (default 1280x720)")
    replay.add_argument("--scale", type=_scale, default=1.0,
                        help="shrink --video frames by this factor (e.g. 0.5 for a gif)")
    replay.add_argument("--plot", metavar="PNG",
                        help="headless: plot joint targets against actual angles over "
                             "time, one subplot per actuated joint (.png, .pdf, .svg or "
                             ".jpg)")
    replay.add_argument("--overlay", choices=["com"],
                        help="com: draw the balance overlay (as F4 in the window) in the "
                             "window and in --video")
    replay.add_argument("--export-motion", metavar="OUT",
                        help="write the performed motion (root position and angle, every "
                             "joint angle, at --fps) to OUT: .bvh (a planar hierarchy named "
                             "after the character's links; Blender imports it) or .csv")
    replay.set_defaults(func=_replay)

    lst = sub.add_parser("list", help="list characters, interfaces, scenes, scripts, logs "
                                      "and your recordings",
                         description="List what can be named on the command line, with "
                                     "each file's one-line description: characters/, "
                                     "interfaces/, assets/scenes/, assets/scripts/, "
                                     "assets/logs/ and recordings/ (the window's own logs).")
    lst.add_argument("kind", nargs="?", choices=KINDS, metavar="KIND", type=_kind,
                     help=f"only this kind: {', '.join(KINDS)}, or the plural as the "
                          f"headings say (interfaces) (default: all)")
    lst.set_defaults(func=_list)

    check = sub.add_parser("check", help="validate data files, logs and clips (exit 0 "
                                         "valid, 2 invalid)",
                           description="Validate files as the app loads them: YAML data "
                                       "files (.yaml: characters, interfaces, scenes, "
                                       "scripts, mocap mappings, bone tables and logs' "
                                       "expectations, NAME.expect.yaml), each told by its "
                                       "folder, name or keys; input logs (.jsonl) as "
                                       "replay reads them (header, every line, the files "
                                       "it names, its expectations; one with expectations "
                                       "needs its end line, as replay --check does), "
                                       "without simulating; "
                                       "BVH clips (.bvh) as mocap info reads them. A name "
                                       "is looked up in every catalog folder (a name in "
                                       "two, such as a script and its log, is refused: "
                                       "give the path). A valid file prints 'FILE: ok "
                                       "(KIND)'; an invalid one a line 'puppet check: "
                                       "FILE:LINE:COL: what is wrong, what was expected'. "
                                       "Exit 0 if all are valid, else 2.")
    check.add_argument("files", nargs="+", metavar="FILE",
                       help="YAML data file(s), logs (.jsonl) or BVH clips (.bvh) to "
                            "validate: paths (characters/luxo.yaml) or names (luxo-mouse, "
                            "cmu-131_01-walk)")
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
    bench.add_argument("--cpu", action="store_true",
                       help="time by the thread's CPU time (a whole process's: its CPU ms), "
                            "not the wall clock (steadier when other processes load the "
                            "machine)")
    bench.set_defaults(func=_bench)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # argparse's parse_args says this as the root parser ("puppet: ...")
        parser.exit(EXIT_DATA_ERROR, f"{args.command_prog}: unrecognized arguments: "
                                     f"{' '.join(extra)} ({args.command_prog} --help)\n")
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return args.func(args)
    except (DataError, UsageError) as exc:  # "puppet mocap send: ...", "puppet play: ..."
        print(f"{args.command_prog}: {exc}", file=sys.stderr)
        return EXIT_DATA_ERROR
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # the output went to a pipe that closed (| head): fine
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0


if __name__ == "__main__":
    sys.exit(main())
