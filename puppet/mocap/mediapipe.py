"""MediaPipe pose over OSC: decode and encode.

One message per frame, ``/mediapipe/pose`` with the 33 pose landmarks in MediaPipe's
order, four numbers each: x, y, z, visibility (132 numbers), optionally preceded by
the sender's time in seconds (133). A landmark whose visibility is below the
decoder's ``threshold`` (default 0.5) is left out of the frame; points are named by
MediaPipe's landmark names (``left_hip`` is number 23), in the sender's axes and units
(MediaPipe's world landmarks: metres, y down).
"""

from __future__ import annotations

from pythonosc.osc_message_builder import OscMessageBuilder

from puppet.mocap.osc import MAX_POSITION, Decoder, Drop, Frame, bounded, frame_time, number

ADDRESS = "/mediapipe/pose"
DEFAULT_PORT = 39570  # no standard port; VMC uses 39539 and 39540
VISIBLE = 0.5  # default threshold: a landmark less visible than this is left out
LANDMARKS = (
    "nose", "left_eye_inner", "left_eye", "left_eye_outer", "right_eye_inner",
    "right_eye", "right_eye_outer", "left_ear", "right_ear", "mouth_left", "mouth_right",
    "left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist",
    "right_wrist", "left_pinky", "right_pinky", "left_index", "right_index",
    "left_thumb", "right_thumb", "left_hip", "right_hip", "left_knee", "right_knee",
    "left_ankle", "right_ankle", "left_heel", "right_heel", "left_foot_index",
    "right_foot_index",
)
VALUES = 4 * len(LANDMARKS)  # 132


class MediaPipeDecoder(Decoder):
    format = "mediapipe"
    default_port = DEFAULT_PORT

    def __init__(self, threshold: float = VISIBLE):
        super().__init__()
        self.threshold = threshold

    def message(self, address: str, args: list) -> Frame | None:
        if address != ADDRESS:
            raise Drop("unknown_address", f"'{address[:40]}' is not {ADDRESS}")
        if args and isinstance(args[0], int) and not isinstance(args[0], bool):
            raise Drop("bad_arguments", f"{ADDRESS}: a leading count of poses ({args[0]}): "
                                        f"the MediaPipe-to-OSC bridge's picture landmarks "
                                        f"(--mocap-format mediapipe-osc reads them)")
        if len(args) not in (VALUES, VALUES + 1):
            raise Drop("bad_arguments", f"{ADDRESS}: {VALUES} numbers (or a time and "
                                        f"{VALUES}) expected, got {len(args)} arguments")
        t = frame_time(args[0]) if len(args) == VALUES + 1 else None
        values = args[len(args) - VALUES:]
        points = {}
        for i, name in enumerate(LANDMARKS):
            x, y, z = (bounded(v, name, MAX_POSITION) for v in values[4 * i: 4 * i + 3])
            seen = number(values[4 * i + 3], f"{name} visibility")
            if not 0.0 <= seen <= 1.0:
                raise Drop("out_of_range", f"{name} visibility {seen:g} is not 0..1")
            if seen >= self.threshold:
                points[name] = (x, y, z)
        return Frame(points=points, time=t)


def encode_frame(time: float | None, points: dict[str, tuple[float, float, float]]) -> bytes:
    """One frame: the landmarks in ``points`` visible (1), the others invisible (0)."""
    builder = OscMessageBuilder(address=ADDRESS)
    if time is not None:
        builder.add_arg(float(time), "f")
    for name in LANDMARKS:
        p = points.get(name)
        for v in (p if p is not None else (0.0, 0.0, 0.0)):
            builder.add_arg(float(v), "f")
        builder.add_arg(1.0 if p is not None else 0.0, "f")
    return builder.build().dgram
