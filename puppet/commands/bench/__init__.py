"""``puppet bench``: how fast the simulation runs, headless, for every shipped character.

For each character (``characters/*.yaml``) it takes the first interface (by file name)
that drives it with the mouse, builds a Session on the interface's scene and measures:

* **control** - simulated seconds per wall second of a Session fed the way the window
  feeds it: one frame = one mouse event (a scripted figure-of-eight gesture; a press or
  release of one of the interface's keys every 0.5 s if it has keys) handed to
  ``Session.handle``, then ``Session.advance`` of 1/60 s of steps. No rendering. This
  is the control layer (devices -> interface runtime -> PD targets -> steps) with the
  timeline's automatic keyframes off; the same run with them on is reported beside it,
  since the timeline has budgets of its own (checkpoint and rewind times, below).
* **bare, same motion** - the same Simulation stepped by pymunk's ``space.step(dt)`` in
  a plain loop (what a plain pymunk program does; the Session steps Chipmunk directly,
  ``step_space``), with the servo targets the control run produced written straight
  onto the pymunk springs between frames (so it goes through the identical trajectory:
  the state hashes are compared). ``control overhead = control time / bare time - 1``
  on this pair, since a different motion costs the physics a different amount.
* **bare, at rest** - the same Simulation stepped with no targets at all (the character
  stands still): shown for information, it is not the same physics work.
* **checkpoint** - ``Simulation.snapshot`` / ``restore`` / ``checkpoint`` times and bytes.
* **rewind** - 60 s of controlled play with the Session's history (keyframes every
  checkpoint interval plus the input events; its memory under ``tracemalloc``); then
  ``Session.rewind_to`` a step 60 s back (restore the keyframe before it, re-simulate the
  input up to it) and one frame of play from there.
* **feat logs** - the control overhead on what users run: every shipped log replayed
  by a Session against bare Chipmunk fed the very writes the controlled run made
  (``feats``: servo targets and gains, velocity changes, grasps, checkpoints' re-seats;
  the bare run must end in the log's own state). ``--feats`` runs this section alone.
* **HUD frames** - a frame with the HUD and F1's key map open on four biped logs,
  replayed and drawn by the window's code (``frames``): p50 / p99 / worst.
* **logs** - replay speed of every ``assets/logs/*.jsonl`` through
  ``puppet.timeline.replay.replay`` with its expectations, as ``puppet.testing.replay_log``
  replays it.

Every time is a median over repeats of ``time.perf_counter`` measurements (``--cpu``:
the measuring thread's CPU time, ``time.thread_time``, steadier when other processes
load the machine; the report says which). The control,
keyframes and bare runs of a repeat are played in turns, 0.5 s of frames each (the order
rotating), so that a machine whose speed drifts - a shared VM's does, by tens of per
cent over seconds - slows them alike; the overhead is the median of the repeats'
control/bare ratios (their range is shown). Targets are reported PASS/MISS; the exit
code is 0 unless ``--strict``.

The package, one measurement a module: ``config`` (clock, run lengths, targets),
``subjects`` (what is measured, the input), ``speed`` (control against bare pymunk),
``checkpoints`` (checkpoint, rewind, scrub), ``channels``, ``feedback``, ``mocap`` and
``latency``, ``logs``, ``feats`` (the feat logs' control overhead), ``frames``,
``processes``;
``suite`` runs them all and ``report`` prints it.
"""

from __future__ import annotations

import argparse
import math


def register(subparsers) -> None:
    """``puppet bench [CHARACTER...]``."""
    bench = subparsers.add_parser("bench",
                                  help="measure simulation speed, checkpoints and rewind",
                                  description="Headless benchmark of every shipped "
                                              "character: speed with control vs bare "
                                              "pymunk, checkpoint and rewind times, log "
                                              "replay speed; PASS/MISS per target.")
    bench.add_argument("character", nargs="*", help="only these characters (default: all)")
    bench.add_argument("--json", action="store_true", help="machine-readable output")
    bench.add_argument("--quick", action="store_true", help="a short run (for tests)")
    bench.add_argument("--strict", action="store_true", help="exit 1 if a target is missed")
    bench.add_argument("--cpu", action="store_true",
                       help="time by the thread's CPU time (a whole process's: its CPU ms), "
                            "not the wall clock (steadier when other processes load the "
                            "machine)")
    bench.add_argument("--feats", action="store_true",
                       help="only the control overhead on the shipped feat logs (each log "
                            "with control against bare Chipmunk fed the same writes)")
    bench.add_argument("--log", action="append", metavar="NAME", dest="logs",
                       help="with --feats: only this shipped log (its name, e.g. "
                            "luxo-hop; repeat for more)")
    bench.add_argument("--soak", type=_minutes, metavar="MINUTES",
                       help="instead: scrub the cat and the biped for MINUTES each (30 for "
                            "the issue's soak) and report the growth of the resident memory "
                            "(exit 1 past 2 MB)")
    bench.set_defaults(func=run)


def _minutes(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 < value <= 24 * 60:
        raise argparse.ArgumentTypeError(f"expected minutes, a number in 0..1440, got {text!r}")
    return value


def run(args: argparse.Namespace) -> int:
    if args.soak is not None:  # the long scrubbing soak instead (soak.py)
        from puppet.commands.bench.soak import soak_main

        return soak_main(args.soak, as_json=args.json)
    import json
    import sys

    from puppet.commands.bench.report import format_feat_report, format_report
    from puppet.commands.bench.suite import run_bench, run_feats

    clock_name = "cpu" if args.cpu else "wall"
    if args.logs and not args.feats:
        from puppet.data.errors import UsageError

        raise UsageError("--log picks feat logs: use it with --feats")
    if args.feats:
        report = run_feats(quick=args.quick, only=args.character or None,
                           clock_name=clock_name, logs=args.logs)
    else:
        report = run_bench(quick=args.quick, only=args.character or None,
                           clock_name=clock_name)
    if args.json:
        json.dump(report, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print((format_feat_report if args.feats else format_report)(report))
    return 1 if args.strict and not report["all_pass"] else 0
