"""``puppet replay``: logs replayed in the window or headless (many at once, in
processes), checked against their expectations, rendered to a video, plotted, or
exported as motion for animators.

The replay engine is ``puppet.timeline.replay`` and what a replay prints is
``puppet.timeline.report``; here are the options and the command that picks the
window, the export or the headless report.
"""

from __future__ import annotations

import argparse
import re
import sys

from puppet.commands import options
from puppet.commands.options import IMAGE_EXTS, PLOT_EXTS, output_file, output_folder
from puppet.data.errors import UsageError


def register(subparsers) -> None:
    """``puppet replay`` and its options."""
    replay = subparsers.add_parser("replay", help="replay input logs (in a window or headless)",
                            description="Replay recorded input logs. Headless prints the "
                                        "final state hash; --check evaluates the log's "
                                        "expectations (exit 1 if one fails).")
    replay.add_argument("logs", nargs="+", metavar="LOG",
                        help="log file(s) (.jsonl), or names (assets/logs/NAME.jsonl, "
                             "else recordings/NAME.jsonl)")
    replay.add_argument("--headless", action="store_true", help="no window, as fast as it goes")
    replay.add_argument("--check", action="store_true",
                        help="evaluate the expectations (header 'expect' or LOG.expect.yaml)")
    replay.add_argument("--until-step", type=options.step, metavar="N",
                        help="stop at step N (the first time the replay is there "
                             "with no more events for it); past the log's end the run "
                             "goes on without input to N, and a note on stderr says so")
    replay.add_argument("--as-recorded", action="store_true",
                        help="replay the interface as recorded in the log (its header's "
                             "copy), not today's file")
    replay.add_argument("--allow-truncated", action="store_true",
                        help="replay the valid lines before a corrupt or cut-off one")
    replay.add_argument("--jobs", "-j", type=options.jobs, default=1, metavar="N",
                        help="replay several logs in N processes (headless)")
    replay.add_argument("--solver-passes", type=options.solver_passes, metavar="N",
                        help="headless: replay on N constraint-solver passes a step instead "
                             "of the character's (its feat judged with --check; the end "
                             "state cannot match): is the feat a knife edge?")
    replay.add_argument("--step", type=options.sim_step, metavar="S",
                        help="headless: replay on a simulation step of S seconds (1/240 "
                             "or 0.0041667), every event moved to the step nearest its "
                             "recorded time (judged as --solver-passes is)")
    replay.add_argument("--slowdown", type=options.slowdown,
                        help="window and --video: override the recorded slowdown "
                             "(0.1-100; 0.25 watches a replay four times faster)")
    replay.add_argument("--video", metavar="OUT",
                        help="headless: render the replay as the window shows it, HUD "
                             "included, to OUT (.mp4, .mov, .mkv, .avi or .gif); the last "
                             "frame is held 1 s more, with the replay's verdict, so that a "
                             "player or a looping gif does not end on the last move")
    replay.add_argument("--screenshot", metavar="PNG",
                        help="headless: write the replay's last frame to this image file "
                             "(.png, .jpg, .bmp or .tga), as play --screenshot does")
    replay.add_argument("--frames", metavar="DIR",
                        help="headless: write every frame (at --fps of simulated time) as "
                             "DIR/frame_N.png (DIR is created), as play --frames does")
    replay.add_argument("--fps", type=options.fps, default=30.0,
                        help="frame rate for --video (1-240, at most 50 for a gif; default "
                             "30), --frames and --export-motion")
    replay.add_argument("--size", type=options.size, default=(1280, 720), metavar="WxH",
                        help="window size drawn for --video, --frames and --screenshot "
                             "(default 1280x720)")
    replay.add_argument("--scale", type=options.scale, default=1.0,
                        help="shrink --video frames by this factor (e.g. 0.5 for a gif)")
    replay.add_argument("--plot", metavar="PNG",
                        help="headless: plot joint targets against actual angles over "
                             "time, one subplot per actuated joint (.png, .pdf, .svg or "
                             ".jpg)")
    replay.add_argument("--overlay", choices=["com"],
                        help="com: draw the balance overlay (as F4 in the window) in the "
                             "window, in --video, --frames and --screenshot")
    replay.add_argument("--export-motion", metavar="OUT",
                        help="write the performed motion (root position and angle, every "
                             "joint angle, at --fps) to OUT: .bvh (a planar hierarchy named "
                             "after the character's links; Blender imports it) or .csv")
    replay.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if _physics(args) and (args.export_motion or args.video or args.plot):
        raise UsageError("--solver-passes and --step go with --check, --frames and "
                         "--screenshot, not --export-motion, --video or --plot (those "
                         "export the recorded run)")
    if args.export_motion:  # headless always: a file for animators, no window
        if args.video or args.plot or args.check or args.frames or args.screenshot:
            raise UsageError("--export-motion goes alone (no --video, --plot, --frames, "
                             "--screenshot or --check)")
        if len(args.logs) != 1:
            raise UsageError("--export-motion takes one log")
        from puppet.timeline.motion import FORMATS, export_motion_command

        output_file("--export-motion", args.export_motion, FORMATS)  # before the replay

        return export_motion_command(args)
    if args.frames or args.screenshot:
        return _images(args)
    if args.video:
        from puppet.app.export import GIF_EXTS, VIDEO_EXTS

        output_file("--video", args.video, tuple(sorted(VIDEO_EXTS | GIF_EXTS)))
    if args.plot:
        output_file("--plot", args.plot, PLOT_EXTS)
    if args.video or args.plot:
        from puppet.app.export import export_command

        return export_command(args)
    import gc

    import puppet.timeline.report  # noqa: F401 - the replay's modules, loaded before the freeze

    # What the imports made (modules, classes, functions) lives as long as the process:
    # out of the collector's way, a full collection during the replay no longer walks
    # it (gc.freeze: about 15 ms of a short headless replay's ~140).
    gc.freeze()
    return replay_command(args)


def _physics(args):
    """The --solver-passes / --step settings (an ``OtherPhysics``, false when none)."""
    physics = options.other_physics(args)
    if physics and getattr(args, "until_step", None) is not None:
        raise UsageError("--until-step counts the log's steps: it does not go with "
                         "--solver-passes or --step")
    return physics


def _images(args: argparse.Namespace) -> int:
    """``--frames DIR`` and ``--screenshot FILE``: the replay's images, drawn by the code
    that draws ``puppet play --headless``'s (``puppet.app.headless.Images``), during the
    one replay whose state line (and, with --check, checks) it prints."""
    if args.video or args.plot:
        raise UsageError("--frames and --screenshot go without --video and --plot (each "
                         "makes its own replay; run them one after the other)")
    if not args.headless:
        raise UsageError("--screenshot and --frames need --headless")
    if len(args.logs) != 1:
        raise UsageError("--frames and --screenshot take one log")
    if args.screenshot:
        output_file("--screenshot", args.screenshot, IMAGE_EXTS)
    if args.frames:
        output_folder("--frames", args.frames)
    from puppet.app.headless import Images
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import find_log, replay
    from puppet.timeline.report import exit_code, print_one, until_note, verdict

    physics = _physics(args)  # the images of the run on other physics, if asked
    if physics:
        print(f"on {physics.label()}: the end state not compared", file=sys.stderr)
    log = read_log(find_log(args.logs[0]), args.allow_truncated)
    slowdown = args.slowdown or float(log.header.get("slowdown") or 1.0)  # the HUD's
    images = Images(args.screenshot, args.frames, args.fps, tuple(args.size), slowdown,
                    overlay=args.overlay == "com")
    every = images.every(physics.dt or float(log.header["dt"]))
    result = replay(log, args.until_step, args.allow_truncated, check=args.check,
                    trajectory=args.check, as_recorded=args.as_recorded,
                    frames=(every, images.frame) if every else None, physics=physics)
    images.finish(result.session)
    res = result.summary
    res["outcomes"] = [str(o) for o in result.outcomes]
    note = until_note(log, args.until_step)
    if note:
        res["warnings"].append(note)
    print_one(res, args.check)
    if args.screenshot:
        print(f"wrote {args.screenshot}")
    if args.frames:
        print(f"wrote {images.written} frames to {args.frames}")
    return exit_code([verdict(res)], bool(res.get("blowups")))


def replay_command(args) -> int:
    """``puppet replay LOG... [--headless] [--check] [--until-step N] [--allow-truncated]
    [--jobs N]``. Exit 2 if a log cannot be replayed, 1 if one fails its expectations
    (--check) or ends in another state than recorded, else 0."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import cut_warnings, find_log, setup_for_log
    from puppet.timeline.report import (
        EXIT_DATA_ERROR,
        exit_code,
        print_notes,
        print_one,
        replay_one,
        results_table,
        summary_line,
        until_note,
        verdict,
    )

    logs = list(args.logs)
    physics = _physics(args)
    if not args.headless:
        if physics:
            raise UsageError("--solver-passes and --step need --headless")
        if len(logs) > 1:
            raise UsageError("several logs need --headless")
        if args.check:
            raise UsageError("--check needs --headless")
        from puppet.app.window import run_window

        log = read_log(find_log(logs[0]), args.allow_truncated)
        setup, warnings = setup_for_log(log, args.as_recorded)
        warnings += cut_warnings(log)
        note = until_note(log, args.until_step)
        if note:
            warnings.append(note)
        for w in warnings:
            print(w, file=sys.stderr)
        slowdown = args.slowdown or float(log.header.get("slowdown") or 1.0)
        return run_window(setup, slowdown, replay=log, until_step=args.until_step,
                          slowdown_chosen=args.slowdown is not None,
                          overlay=getattr(args, "overlay", None) == "com",
                          note=" / ".join(re.sub(r"^.*?: (warning|note): ", "", w)
                                          for w in warnings))

    if physics:  # said once, before the results: no hash is compared
        print(f"on {physics.label()}: the expectations judged, the end state not compared",
              file=sys.stderr)
    if len(logs) == 1 and args.jobs <= 1:
        res = replay_one(logs[0], args.until_step, args.allow_truncated, args.check,
                         args.as_recorded, physics)
        if "error" in res:
            print(f"puppet replay: {res['error']}", file=sys.stderr)
            return EXIT_DATA_ERROR
        print_one(res, args.check)
        return exit_code([verdict(res)], bool(res.get("blowups")))

    from tqdm import tqdm

    params = (args.until_step, args.allow_truncated, args.check, args.as_recorded, physics)
    results: dict[int, dict] = {}
    # disable=None: a bar on a terminal, nothing when stderr is a file or a pipe
    bar = tqdm(total=len(logs), unit="log", desc="replay", file=sys.stderr, disable=None)
    if args.jobs > 1:
        from concurrent.futures import ProcessPoolExecutor, as_completed

        with ProcessPoolExecutor(max_workers=args.jobs) as pool:
            futures = {pool.submit(replay_one, p, *params): i for i, p in enumerate(logs)}
            for fut in as_completed(futures):
                results[futures[fut]] = fut.result()
                bar.update(1)
    else:
        for i, p in enumerate(logs):
            results[i] = replay_one(p, *params)
            bar.update(1)
    bar.close()
    ordered = [results[i] for i in range(len(logs))]
    for r in ordered:
        if "error" in r:
            print(f"puppet replay: {r['error']}", file=sys.stderr)
    for r in ordered:
        print_notes(r)
        if args.check and "error" not in r:
            for line in r["failed"]:
                print(f"{r['log']}: {line}")
    print(results_table(ordered, args.check))
    print(summary_line(ordered, args.check))
    return exit_code([verdict(r) for r in ordered], any(r.get("blowups") for r in ordered))
