"""puppet's own OSC address: named channels, no mapping needed.

``/puppet/channels [time] name value name value ...``: one frame of channels, read
by an interface as ``channel.NAME`` (section 5.6 of the designer's guide). The time
(seconds, optional) comes first if given. Names are channel names (a letter or ``_``,
then letters, digits, ``_ . -``); values are numbers within +-1e6; names starting
``mocap.`` are kept for puppet's own and may not be sent.
"""

from __future__ import annotations

import re

from pythonosc.osc_message_builder import OscMessageBuilder

from puppet.mocap.osc import Decoder, Drop, Frame, bounded, frame_time, text

ADDRESS = "/puppet/channels"
DEFAULT_PORT = 39571
MAX_VALUE = 1.0e6  # the input range a log holds
MAX_NAMES = 512
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]{0,63}")
RESERVED = "mocap."


class PuppetDecoder(Decoder):
    format = "puppet"
    default_port = DEFAULT_PORT

    def __init__(self):
        super().__init__()
        self.last: dict[str, float] = {}  # the channels of the frames at the last time

    def novel(self, frame: Frame) -> bool:
        """Channels at the last frame's time that it had not (or had otherwise): the
        frame's next part (a frame of more channels than one datagram holds)."""
        return any(self.last.get(n) != v for n, v in frame.channels.items())

    def finish(self, frame: Frame) -> Frame:
        if frame.time is not None and frame.time != self._time:
            self.last = {}
        self._time = frame.time
        self.last.update(frame.channels)
        return frame

    _time: float | None = None

    def message(self, address: str, args: list) -> Frame | None:
        if address != ADDRESS:
            raise Drop("unknown_address", f"'{address[:40]}' is not {ADDRESS}")
        t = None
        if len(args) % 2 == 1:
            t = frame_time(args[0])
            args = args[1:]
        if not args or len(args) > 2 * MAX_NAMES:
            raise Drop("bad_arguments", f"{ADDRESS}: 1 to {MAX_NAMES} name, value pairs "
                                        f"expected, got {len(args)} arguments")
        channels = {}
        for i in range(0, len(args), 2):
            name = text(args[i], f"{ADDRESS} argument {i + 1}")
            if not NAME.fullmatch(name) or name.startswith(RESERVED):
                raise Drop("bad_arguments", f"{ADDRESS}: '{name[:40]}' is not a channel "
                                            f"name one may send")
            channels[name] = bounded(args[i + 1], name, MAX_VALUE)
        return Frame(channels=channels, time=t)


def encode_frame(time: float | None, channels: dict[str, float]) -> bytes:
    builder = OscMessageBuilder(address=ADDRESS)
    if time is not None:
        builder.add_arg(float(time), "f")
    for name, value in channels.items():
        builder.add_arg(str(name), "s")
        builder.add_arg(float(value), "f")
    return builder.build().dgram
