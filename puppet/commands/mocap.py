"""``puppet mocap info``, ``send`` and ``listen``: a clip's contents, a clip streamed
over OSC as a live source would, and what arrives on a port.

Only argparse is imported at the top: the command line starts fast; each command
imports what it needs.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from puppet.commands.streams import FORMATS, retargeter_for
from puppet.data.errors import UsageError

DEFAULT_BONES = "assets/mocap/cmu-bones.yaml"
MAX_SPEED = 10.0


def _speed(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.05 <= value <= MAX_SPEED:
        raise argparse.ArgumentTypeError(f"'{text}' is not a speed from 0.05 to {MAX_SPEED:g} "
                                         f"(1 plays the clip in real time)")
    return value


def drop_option(text: str) -> tuple[float, float]:
    """``FROM:UNTIL`` seconds (argparse's type for ``--mocap-drop``)."""
    a, sep, b = text.partition(":")
    try:
        lo, hi = float(a), float(b)
    except ValueError:
        lo = hi = float("nan")
    if not (sep and 0.0 <= lo < hi <= 3600.0):
        raise argparse.ArgumentTypeError(f"'{text}' is not FROM:UNTIL, seconds with FROM "
                                         f"before UNTIL (e.g. 4.5:6)")
    return lo, hi


def _duration(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0.0 < value <= 24 * 3600.0:
        raise argparse.ArgumentTypeError(f"'{text}' is not a duration in seconds "
                                         f"(more than 0, at most a day)")
    return value


def _project_file(path: str) -> Path:
    """A path as given, else relative to the project (so a default works from anywhere)."""
    p = Path(path)
    if p.exists() or p.is_absolute():
        return p
    root = Path(__file__).resolve().parents[2]
    return root / p if (root / p).exists() else p


def register(subparsers) -> None:
    """``puppet mocap`` and its sub-commands ``info``, ``send`` and ``listen``."""
    mocap = subparsers.add_parser("mocap", help="motion capture: what a clip holds; stream a "
                                                "clip live, watch a stream",
                                  description="Motion-capture clips and streams: a clip's "
                                              "skeleton and angles; send a BVH clip over "
                                              "OSC as a live source would; listen and "
                                              "print what arrives.")
    msub = mocap.add_subparsers(dest="mocap_command", metavar="WHAT", required=True)
    info = msub.add_parser("info", help="a clip's skeleton, frame rate, length and the "
                                        "planar angles it would give")
    info.add_argument("clip", help="a BVH file, or a name: assets/mocap/NAME.bvh")
    info.add_argument("--mapping", help="the mapping (assets/mappings/NAME.yaml or a path); "
                                        "default: the first whose points the clip has "
                                        "(by name)")
    info.set_defaults(func=_info)
    from puppet.commands.mocap_mapping import register as register_rig_mapping

    register_rig_mapping(msub)  # puppet mocap mapping CLIP: a recognised rig's mapping
    from puppet.commands.mocap_library import register as register_library

    register_library(msub)  # puppet mocap library FOLDER: a motion library
    send = msub.add_parser("send", help="stream a BVH clip over OSC in real time",
                           description="Stream a BVH clip over OSC/UDP in real time "
                                       "(VMC bones, MediaPipe landmarks, or puppet "
                                       "channels through a mapping).")
    send.add_argument("clip", metavar="CLIP",
                      help="a BVH file, or a name: assets/mocap/NAME.bvh")
    send.add_argument("--to", default="udp://127.0.0.1:39539", metavar="udp://HOST:PORT",
                      help="where to send (default udp://127.0.0.1:39539)")
    send.add_argument("--format", choices=FORMATS, default="vmc",
                      help="vmc (default), mediapipe, mediapipe-osc (as the "
                           "MediaPipe-to-OSC bridge: the clip filmed side-on), or puppet "
                           "(needs --mapping)")
    send.add_argument("--bones", default=DEFAULT_BONES, metavar="FILE",
                      help="which BVH joint is which humanoid bone / landmark (vmc and "
                           f"mediapipe; default {DEFAULT_BONES})")
    send.add_argument("--mapping", metavar="NAME",
                      help="puppet format: the mapping that makes the clip's channels")
    send.add_argument("--speed", type=_speed, default=1.0,
                      help="playback speed (0.05-10; default 1, real time)")
    send.add_argument("--loop", action="store_true", help="start again at the end, for ever")
    send.add_argument("--quiet", "-q", action="store_true", help="print nothing while sending")
    send.set_defaults(func=_send)
    listen = msub.add_parser("listen", help="print what arrives on an OSC port",
                             description="Listen for a live OSC stream and print, every "
                                         "second, what arrives: packets, frames, rate, "
                                         "drops by reason, the points or channels seen.")
    listen.add_argument("--port", type=int, metavar="N",
                        help="UDP port (default: the format's, 39539 for vmc)")
    listen.add_argument("--host", default="127.0.0.1",
                        help="address to bind (default 127.0.0.1; 0.0.0.0 for every "
                             "network)")
    listen.add_argument("--format", choices=FORMATS, default="vmc",
                        help="what to expect: vmc (default), mediapipe, mediapipe-osc or "
                             "puppet")
    listen.add_argument("--mapping", metavar="NAME",
                        help="also show the channels this mapping makes of the points")
    listen.add_argument("--seconds", type=_duration, metavar="S",
                        help="stop after S seconds (default: until Ctrl+C)")
    listen.set_defaults(func=_listen)


def _info(args: argparse.Namespace) -> int:
    from puppet.mocap.info import describe

    notes: list[str] = []
    print(describe(args.clip, args.mapping, notes))
    for note in notes:  # e.g. a performer 0.10 m tall: a unit wrong
        print(f"puppet mocap info: warning: {note}", file=sys.stderr)
    return 0


def _send(args: argparse.Namespace) -> int:
    from puppet.data.catalog import find
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.formats import parse_udp
    from puppet.mocap.send import encoder, load_bones, stream

    address = parse_udp("--to", args.to, 39539)
    clip_path = find("clip", args.clip)  # a path, or a name as mocap info and --mocap take
    clip = read_bvh(clip_path)
    table = retargeter = None
    if args.format == "puppet":
        if args.mapping is None:
            raise UsageError("--format puppet sends the clip's channels: give --mapping NAME "
                             "(e.g. cmu-131)")
        retargeter = retargeter_for(args.mapping)
    else:
        table = load_bones(_project_file(args.bones))
    encode = encoder(clip, args.format, table, retargeter)
    from puppet.mocap.info import height_note, mapping_unit_note

    note = (mapping_unit_note(clip, retargeter.mapping, find("mapping", args.mapping))
            if table is None else
            height_note(clip, table.unit, table.up, f"the bone table's unit in {table.path}"))
    if note:  # a clip in metres through a centimetre table streams a 10 cm performer
        print(f"puppet mocap send: warning: {note}", file=sys.stderr)
    seconds = clip.frames * clip.frame_time / args.speed
    if not args.quiet:
        print(f"sending {clip_path.name} ({clip.frames} frames at {clip.fps:.4g} fps, "
              f"{seconds:.1f} s{', looping' if args.loop else ''}) as {args.format} to "
              f"udp://{address[0]}:{address[1]}; Ctrl+C stops", flush=True)

    def progress(sent: int) -> None:
        if not args.quiet and sent % max(1, round(clip.fps)) == 0:
            print(f"\r{sent} frames sent", end="", flush=True)

    try:
        sent = stream(encode, clip.frames, clip.frame_time, address, args.speed, args.loop,
                      on_sent=progress)
    except KeyboardInterrupt:
        print()
        return 130
    if not args.quiet:
        print(f"\r{sent} frames sent")
    return 0


def _listen(args: argparse.Namespace) -> int:
    from puppet.mocap.formats import decoder
    from puppet.mocap.source import OscSource

    port = args.port if args.port is not None else decoder(args.format).default_port
    if not 0 <= port <= 65535:
        raise UsageError(f"--port {port}: expected a whole number 0..65535")
    from puppet.mocap.formats import parse_udp

    host, _ = parse_udp("--host", f"{args.host}:{port}", port, listening=True)
    source = OscSource(args.format, host, port, retargeter=retargeter_for(args.mapping))
    source.start()
    print(f"listening for {args.format} on udp://{source.host}:{source.port}; Ctrl+C stops",
          flush=True)
    start = time.perf_counter()
    names_shown: tuple = ()
    reasons_shown: set[str] = set()
    try:
        while args.seconds is None or time.perf_counter() - start < args.seconds:
            time.sleep(min(1.0, args.seconds - (time.perf_counter() - start))
                       if args.seconds is not None else 1.0)
            events = source.drain()
            print(source.status(), flush=True)
            for kind, text in source.reasons():  # once a kind: why the first was dropped
                if kind not in reasons_shown:
                    reasons_shown.add(kind)
                    print(f"  {kind}: {text}{_format_hint(text, args.format)}", flush=True)
            if source.last_names and source.last_names != names_shown:
                names_shown = source.last_names
                print(f"  {len(names_shown)} named: {', '.join(names_shown)}", flush=True)
            values = next((e["values"] for e in reversed(events) if e["type"] == "channels"),
                          None)  # (a lost stream's event is a lone channel)
            if values:
                shown = ", ".join(f"{n}={v:.3g}" for n, v in list(values.items())[:12])
                more = f" (+{len(values) - 12})" if len(values) > 12 else ""
                print(f"  channels: {shown}{more}", flush=True)
    except KeyboardInterrupt:
        pass
    finally:
        source.close()
    print(source.status())
    return 0


ADDRESS_FORMATS = (("/VMC/", "vmc"), ("/mediapipe/pose", "mediapipe"),
                   ("/puppet/channels", "puppet"))  # an address's beginning: whose it is
# (mediapipe-osc's address is mediapipe's: a leading count says which, in the drop's words)


def _format_hint(text: str, fmt: str) -> str:
    """A drop that quotes another format's address (``'/mediapipe/pose' is not a VMC
    address``): which --format would take it; else nothing."""
    if not text.startswith("'"):
        return ""
    address = text[1:].split("'", 1)[0]
    for prefix, other in ADDRESS_FORMATS:
        if other != fmt and address.startswith(prefix):
            return f" (a {other} address: listen --format {other}?)"
    return ""
