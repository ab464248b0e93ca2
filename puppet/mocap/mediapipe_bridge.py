"""The common MediaPipe-to-OSC bridge's pose messages, as published (cansik's
mediapipe-osc, ``pose.py``; its README's "Format"): decode and encode.

``/mediapipe/pose count x y z visibility ...``: ``count`` (an int: how many poses were
found, 0 or 1) then 33 landmarks of four floats for each pose; a message of ``0``
alone is "no pose" (the tracker lost the performer). The landmarks are MediaPipe's
*normalised image* landmarks: x across the picture (0 left .. 1 right, in picture
widths), y down it (in picture heights), z a depth in about x's scale that MediaPipe
says to discard, visibility 0..1. The bridge flips the camera picture for a selfie view
before MediaPipe sees it, so what it calls a left hip is the performer's right, seen
mirrored: the decoder unmirrors (x becomes 1 - x, left and right swap back) unless
told the sender does not mirror. The bridge's older form - no count, 33 (or, upper
body only, 25) landmarks - is read too. The bridge sends no time.

A frame's points are named as MediaPipe names the landmarks (``left_hip``) in the
picture's axes; ``assets/mappings/mediapipe-image.yaml`` reads them: up is -y, x is
scaled to the picture's aspect, z dropped, the performer side-on to the camera faces
the way the near foot points.
"""

from __future__ import annotations

from pythonosc.osc_message_builder import OscMessageBuilder

from puppet.mocap.mediapipe import ADDRESS, LANDMARKS
from puppet.mocap.osc import Decoder, Drop, Frame, bounded, number

DEFAULT_PORT = 7500  # the bridge's default
VISIBLE = 0.5
PICTURE = 10.0  # picture sizes from its middle: beyond is garbage (a landmark may be off it)
UPPER_BODY = 25  # landmarks of the bridge's --upper-body-only model
VALUES = 4 * len(LANDMARKS)


def _swapped(name: str) -> str:
    if name.startswith("left_"):
        return "right_" + name[5:]
    if name.startswith("right_"):
        return "left_" + name[6:]
    return name


class MediaPipeBridgeDecoder(Decoder):
    format = "mediapipe-osc"
    default_port = DEFAULT_PORT

    def __init__(self, mirrored: bool = True, threshold: float = VISIBLE):
        super().__init__()
        self.mirrored = mirrored
        self.threshold = threshold
        self.names = [_swapped(n) for n in LANDMARKS] if mirrored else list(LANDMARKS)

    def message(self, address: str, args: list) -> Frame | None:
        if address != ADDRESS:
            raise Drop("unknown_address", f"'{address[:40]}' is not {ADDRESS}")
        if args and isinstance(args[0], int) and not isinstance(args[0], bool):
            count, values = args[0], args[1:]
            if count == 0 and not values:
                self.counts.no_pose += 1  # the performer left the picture: no sample
                return None
            if not 1 <= count <= 16 or len(values) != count * VALUES:
                raise Drop("bad_arguments", f"{ADDRESS}: a count of poses then 33 landmarks "
                                            f"(4 numbers each) per pose expected; got a count "
                                            f"of {count} and {len(values)} numbers")
            values = values[:VALUES]  # the first pose
        elif len(args) in (VALUES, 4 * UPPER_BODY):  # the older form: no count
            values = args
        else:
            raise Drop("bad_arguments", f"{ADDRESS}: a count and {VALUES} numbers (or "
                                        f"{VALUES} alone) expected, got {len(args)} arguments")
        points = {}
        for i in range(len(values) // 4):
            name = self.names[i]
            x, y, z = (bounded(v, name, PICTURE) for v in values[4 * i: 4 * i + 3])
            seen = number(values[4 * i + 3], f"{name} visibility")
            if not 0.0 <= seen <= 1.0:
                raise Drop("out_of_range", f"{name} visibility {seen:g} is not 0..1")
            if seen >= self.threshold:
                points[name] = (1.0 - x if self.mirrored else x, y, z)
        return Frame(points=points)


def encode_pose(points: dict[str, tuple[float, float, float]] | None,
                mirrored: bool = True, count: bool = True) -> bytes:
    """One message as the bridge sends it: ``points`` (normalised picture landmarks of
    the performer, unmirrored) mirrored as its selfie view is, the landmarks not in
    ``points`` invisible (a point of four values carries its visibility, else 1);
    None: the "no pose" message."""
    builder = OscMessageBuilder(address=ADDRESS)
    if points is None:
        builder.add_arg(0, "i")
        return builder.build().dgram
    if count:
        builder.add_arg(1, "i")
    for name in LANDMARKS:
        p = points.get(_swapped(name) if mirrored else name)
        if p is None:
            builder.add_arg(0.0, "f"), builder.add_arg(0.0, "f"), builder.add_arg(0.0, "f")
            builder.add_arg(0.0, "f")
            continue
        x, y, z, seen = (*p, 1.0) if len(p) == 3 else p
        for v in (1.0 - x if mirrored else x, y, z, seen):
            builder.add_arg(float(v), "f")
    return builder.build().dgram
