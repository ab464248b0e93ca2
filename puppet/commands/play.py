"""``puppet play``: an interface in a window, or headless with a script, a clip or a
live stream; images of what the window shows; the run recorded as a log.

argparse's options are declared in ``register``; ``run`` imports what the run needs.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from puppet.commands import options
from puppet.commands.options import EXIT_BLOWUP, IMAGE_EXTS, output_file, output_folder
from puppet.commands.streams import FORMATS, is_live, source_for
from puppet.data.errors import UsageError


def register(subparsers) -> None:
    """``puppet play`` and its options."""
    play = subparsers.add_parser("play", help="play an interface in a window (or headless)",
                          description="Open a window and drive the interface's character. "
                                      "With --headless, run a scripted input and write "
                                      "images of what the window shows.")
    play.add_argument("interface", help="interface name (interfaces/NAME.yaml) or path")
    play.add_argument("--scene", help="scene name (assets/scenes/NAME.yaml) or path; "
                                      "default: the interface's")
    play.add_argument("--slowdown", type=options.slowdown,
                      help="wall seconds per simulated second (0.1-100; below 1 is faster "
                           "than real time); default: the interface's")
    play.add_argument("--headless", action="store_true", help="no window")
    play.add_argument("--input", metavar="SCRIPT",
                      help="scripted input (assets/scripts/NAME.yaml or path): timed events "
                           "and rules that react to what happens (docs/scripts.md); in the "
                           "window it plays as you watch, headless it runs alone")
    play.add_argument("--seconds", type=options.seconds, help="simulated seconds to run headless "
                                                    "(default: the script's, else 5)")
    play.add_argument("--screenshot", metavar="PNG",
                      help="headless: write the final frame to this image file (.png, .jpg, "
                           ".bmp or .tga)")
    play.add_argument("--frames", metavar="DIR",
                      help="headless: write every frame as DIR/frame_N.png (DIR is created)")
    play.add_argument("--fps", type=options.fps, default=30.0,
                      help="frame rate for --frames (1-240, default 30)")
    play.add_argument("--record", metavar="PATH",
                      help="write the input log here, a new file: an existing PATH is an "
                           "error (default in a window: recordings/INTERFACE-DATE-TIME.jsonl)")
    play.add_argument("--no-record", action="store_true", help="do not record a log")
    play.add_argument("--checkpoint-every", type=options.checkpoint_every, metavar="SECONDS",
                      help="simulated seconds between automatic checkpoints (0.5-600; "
                           "default: the interface's checkpoint_every, else 3)")
    play.add_argument("--ghost", metavar="LOG",
                      help="replay this log as a translucent ghost beside the character, "
                           "in step with its time (the ghost does not touch the live run)")
    play.add_argument("--mocap", metavar="CLIP|udp://HOST:PORT|webcam:N|video:PATH",
                      help="drive the figure with a motion-capture clip (.bvh, or a name: "
                           "assets/mocap/NAME.bvh), played in sim time through the "
                           "interface's mapping; headless runs last the clip's length "
                           "unless --seconds says otherwise. Or a live OSC stream, "
                           "udp://127.0.0.1:39539 (see --mocap-format), paced in real "
                           "time and recorded; or a camera (webcam:0) or a film "
                           "(video:PATH) through MediaPipe's pose landmarker, side-on "
                           "(pip install 'puppet[webcam]')")
    play.add_argument("--loop", action="store_true",
                      help="play the --mocap clip over and over (headless: needs --seconds, "
                           "a looping clip has no end)")
    from puppet.commands.mocap import drop_option

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
    play.add_argument("--virtual-pad", action="store_true",
                      help="try a gamepad layout with no pad: the mouse is the left stick "
                           "(hold the right button: the right stick), the left button the "
                           "right trigger, i j k l the face buttons y x a b, the arrows the "
                           "d-pad, u o the shoulders, return start; logged as a gamepad")
    play.add_argument("--mocap-format", choices=FORMATS, default="vmc",
                      help="--mocap udp://...: what the stream sends: vmc (default, port "
                           "39539), mediapipe (/mediapipe/pose world landmarks, port 39570), "
                           "mediapipe-osc (the MediaPipe-to-OSC bridge: a count, picture "
                           "landmarks, mirrored; port 7500) or puppet (/puppet/channels: "
                           "channels, no mapping)")
    play.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from puppet.data.catalog import find, load_setup
    from puppet.timeline.log import EXISTS
    from puppet.timeline.script import load_script

    if args.input and Path(args.input).suffix.lower() == ".jsonl":  # not a YAML error
        raise UsageError(f"--input {args.input}: a .jsonl file is a recorded log, not a "
                         f"script (assets/scripts/NAME.yaml); play it back with: "
                         f"puppet replay {args.input}")
    if not args.headless and (args.screenshot or args.frames):
        raise UsageError("--screenshot and --frames need --headless")
    if args.headless and args.virtual_pad:  # a script moves the pad itself
        raise UsageError("--virtual-pad is for the window; headless, a script's gamepad: "
                         "entries move the sticks (docs/scripts.md)")
    if args.record and Path(args.record).exists():  # a log is never silently overwritten
        raise UsageError(f"--record {args.record}: {EXISTS}")
    if args.screenshot:
        output_file("--screenshot", args.screenshot, IMAGE_EXTS)
    if args.frames:
        output_folder("--frames", args.frames)
    script = None
    if args.input:
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

        check_links(script_path, script, [link.name for link in setup.character.links],
                    setup.interface, setup.character)
    from puppet.physics.holds import setup_hold_warnings

    setup = setup_hold_warnings(setup)  # (a world-frame hold against a light free side)
    for w in setup.warnings:  # valid but probably not meant (two maps on one joint)
        print(w, file=sys.stderr)
    if args.checkpoint_every is not None:  # the interface's checkpoint_every, overridden
        import dataclasses

        setup = dataclasses.replace(setup, interface=setup.interface.model_copy(
            update={"checkpoint_every": args.checkpoint_every}))
    live = _live_take(args, setup)  # --mocap: a live take (window or headless)
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
        from puppet.data.tracking import interface_mapping_problem

        problem = interface_mapping_problem(setup.interface, setup.character, mapping)
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
                          sources=[clip] if clip is not None else (),
                          virtual_pad=args.virtual_pad, script=script,
                          script_text=_script_text(script_path) if script else None)
    from puppet.app.headless import run_headless
    from puppet.physics.simulation import step_of
    from puppet.timeline.script import compile_script, late_note, run_seconds

    dt = step_of(setup.character)  # the step the session runs on (run_headless's Session)
    events = compile_script(script, dt) if script is not None else []
    seconds = run_seconds(script, args.seconds)
    if clip is not None:
        if args.seconds is None and (script is None or script.seconds is None):
            seconds = clip.clip.duration  # a clip's run lasts the clip
        events = sorted(events + clip.events(dt, seconds), key=lambda e: e[0])
    late = (late_note(script, seconds, dt, args.seconds is not None, clip is not None)
            if script else None)
    if late:  # entries as written, and how long the script runs
        print(f"puppet play: warning: {late}", file=sys.stderr)
    # --record writes the scripted run as a log (see ``puppet replay``); images too
    session = run_headless(setup, events, seconds, args.screenshot, args.frames, args.fps,
                           slowdown=args.slowdown, record=args.record,
                           description=(script.description or None) if args.input else None,
                           ghost=ghost, overlay=args.overlay == "com",
                           rules=script if script is not None and script.rules else None,
                           script=_script_text(script_path) if script is not None else None)
    if args.record:
        print(f"recorded {args.record}")
    print(end_line(session))
    if args.screenshot:
        print(f"wrote {args.screenshot}")
    if args.frames:
        print(f"wrote {session.frames_written} frames to {args.frames}")
    return blowup_exit(session)


def _script_text(path) -> tuple[str, str]:
    """(name, text) of a script, for the header of a log it plays (a playtest plays its
    rules again)."""
    from puppet.data.yamlfile import read_text

    return Path(path).stem, read_text(path)


def end_line(session) -> str:
    """How a headless play ended: time, centre of mass, upright (over the last second,
    when the run kept an ``upright_watch``), the state's hash; a halted run says so
    instead of where the figure is (``timeline.blowups.end_words``)."""
    from puppet.timeline.blowups import end_words

    halted = end_words(session)
    if halted is not None:
        return f"t={session.time:.3f}s  {halted}  state={session.sim.state_hash()}"
    c = session.character
    x, y = c.com()
    watch = getattr(session, "upright_watch", None)
    upright = watch.said(session) if watch is not None else f"upright={c.upright()}"
    return (f"t={session.time:.3f}s  com=({x:.3f}, {y:.3f}) m  {upright}  "
            f"state={session.sim.state_hash()}")


def blowup_exit(session, prog: str = "puppet play") -> int:
    """A headless play's exit code: its blow-ups on stderr, each kind once with a count
    (the window shows them; here nothing would), then EXIT_BLOWUP if there was one,
    else 0. A clip run and a live take (``_live_take``) end through here."""
    from puppet.timeline.blowups import fold

    for note in fold(session.blowup_messages):
        print(f"{prog}: {note}", file=sys.stderr)
    return EXIT_BLOWUP if session.blowups else 0


def _live_take(args, setup) -> int | None:
    """``puppet play ... --mocap URL``: the window or a headless real-time take.
    None when --mocap is not given."""
    if not is_live(args.mocap):
        return None
    if args.input or args.frames or args.ghost or getattr(args, "loop", False) \
            or getattr(args, "mocap_drop", None):
        raise UsageError("--mocap udp://... goes without --input, --frames, --ghost, "
                         "--loop and --mocap-drop (a live take is the performer's: record "
                         "it with --record "
                         "LOG; then puppet replay LOG --video OUT renders its frames, "
                         "and play --ghost LOG shows it beside another run)")
    source = source_for(args.mocap, args.mocap_format, args.mapping, setup)
    source.start()
    print(source.listening_line(), flush=True)
    try:
        if not args.headless:
            from puppet.app.window import run_window

            return run_window(setup, args.slowdown, record=args.record,
                              no_record=args.no_record, overlay=args.overlay == "com",
                              sources=[source])
        from puppet.app.live import run_live

        seconds = args.seconds if args.seconds is not None else 5.0
        session = run_live(setup, [source], seconds,
                           record=None if args.no_record else args.record,
                           slowdown=args.slowdown,
                           description=f"a live {source.format} take from {args.mocap}")
    finally:
        source.close()
    print(source.status())
    if args.record and not args.no_record:
        print(f"recorded {args.record}")
    if args.screenshot:
        from puppet.app.frame import FrameRenderer

        renderer = FrameRenderer(session)
        renderer.info.sources = (source.hud_line(),)
        renderer.save(session, args.screenshot)
        print(f"wrote {args.screenshot}")
    print(end_line(session))
    return blowup_exit(session)  # each blow-up said on stderr, as a clip run says them
