"""What every OSC decoder shares: parsing a datagram, judging numbers, counting drops.

A datagram is parsed by python-osc (``OscBundle`` / ``OscMessage``; nested bundles are
flattened in order). Nothing here raises on bad input: a decoder turns every problem
into a *drop*, counted by its reason in ``Counts``, and goes on with the next packet.

Reasons (``DROP_REASONS``):

* ``malformed``: the bytes are not an OSC message or bundle;
* ``unknown_address``: an address the format does not have;
* ``bad_arguments``: the wrong number or types of arguments, or an unknown name;
* ``not_finite``: a NaN or an infinity;
* ``out_of_range``: a number beyond what the format allows (``MAX_POSITION`` ...);
* ``out_of_order``: the frame's time is before the last frame's;
* ``stale``: the frame's time is the last frame's and it brings nothing new (a repeated
  frame). A frame with the last one's time that does bring something (VMC bones, puppet
  channels the last did not have or had otherwise) goes on with it: a sender that
  spreads one frame over several bundles (one time, many bones) is counted in
  ``continued``, its parts handed out as they come.

The first five judge a datagram (``malformed`` when it does not parse, or one element
of a bundle that does not) or one message of it (the others of a bundle still count);
the last two judge a whole frame. Every
message is accepted, ignored or dropped: ``messages == accepted + ignored +`` the
message drops.

Time going back by more than ``RESTART_GAP`` seconds is taken as the sender starting
again (counted as ``restarts``, not dropped).
"""

from __future__ import annotations

import collections
import logging
import math
import threading
from dataclasses import dataclass, field

from pythonosc import osc_bundle, osc_message

DROP_REASONS = ("malformed", "unknown_address", "bad_arguments", "not_finite",
                "out_of_range", "out_of_order", "stale")
MAX_POSITION = 100.0  # metres (VMC) or MediaPipe units from the origin: beyond is garbage
MAX_TIME = 1.0e10  # a frame time (seconds) beyond this is garbage
RESTART_GAP = 2.0  # seconds: time going back further than this is a new stream
MAX_DATAGRAM = 65536  # the largest UDP payload


class Drop(Exception):
    """Raised inside a decoder (never out of it) to drop a packet for ``reason``."""

    def __init__(self, reason: str, detail: str = ""):
        super().__init__(detail or reason)
        self.reason = reason
        self.detail = detail or reason


@dataclass
class Frame:
    """One decoded sample: named points (x, y, z in the source's axes and units) or
    named channels, and the sender's time (seconds) if it gave one."""

    points: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    channels: dict[str, float] = field(default_factory=dict)
    time: float | None = None


@dataclass
class Counts:
    """What a decoder has seen: packets (datagrams), messages in them, frames made,
    packets or messages dropped by reason, messages ignored (valid addresses of the
    format that puppet does not use), restarts of the sender's clock."""

    packets: int = 0
    messages: int = 0
    accepted: int = 0  # messages judged good (each message is accepted, ignored or dropped)
    frames: int = 0
    ignored: int = 0
    restarts: int = 0
    continued: int = 0  # frames that went on with the last one's time (several bundles)
    no_pose: int = 0  # "no pose" messages (a pose tracker that lost the performer)
    skipped: int = 0  # bundle elements python-osc could not read (each a malformed drop)
    dropped: collections.Counter = field(default_factory=collections.Counter)
    last_problem: str = ""
    first_detail: dict = field(default_factory=dict)  # reason -> what its first drop said

    def drop(self, reason: str, detail: str = "") -> None:
        assert reason in DROP_REASONS, reason
        self.dropped[reason] += 1
        self.last_problem = detail or reason
        self.first_detail.setdefault(reason, detail or reason)

    @property
    def total_dropped(self) -> int:
        return sum(self.dropped.values())

    def drops_text(self) -> str:
        """e.g. ``"3 dropped (2 not_finite, 1 malformed)"``, or ``"0 dropped"``."""
        if not self.total_dropped:
            return "0 dropped"
        parts = ", ".join(f"{n} {r}" for r, n in sorted(self.dropped.items(),
                                                        key=lambda kv: (-kv[1], kv[0])))
        return f"{self.total_dropped} dropped ({parts})"


class _PythonOscWarnings(logging.Filter):
    """python-osc logs (on the root logger) and skips what it cannot read: a bundle
    element that is neither a message nor a bundle, an argument of an unknown type.
    A stream of garbage would flood the terminal; instead those records are counted,
    per thread, and the decoder counts them as drops."""

    def __init__(self):
        super().__init__()
        self.local = threading.local()

    def filter(self, record: logging.LogRecord) -> bool:
        if "pythonosc" not in (record.pathname or ""):
            return True
        message = str(record.msg)
        if message.startswith("Could not identify content type"):
            self.local.elements = getattr(self.local, "elements", 0) + 1
            return False
        if message.startswith("Unhandled parameter type"):
            self.local.types = getattr(self.local, "types", 0) + 1
            return False
        return True

    def take(self) -> tuple[int, int]:
        """(skipped bundle elements, skipped arguments) since the last take."""
        out = (getattr(self.local, "elements", 0), getattr(self.local, "types", 0))
        self.local.elements = self.local.types = 0
        return out


_WARNINGS = _PythonOscWarnings()
logging.getLogger().addFilter(_WARNINGS)


def messages_of(dgram: bytes, counts: "Counts | None" = None
                ) -> tuple[list[osc_message.OscMessage], bool]:
    """The messages of a datagram in order (nested bundles flattened) and whether it
    was a bundle. Raises ``Drop("malformed")`` if python-osc cannot parse it, or if it
    skipped an argument of a type it does not know; a bundle element it could not
    identify (and skipped) is counted in ``counts`` as a ``malformed`` drop."""
    _WARNINGS.take()
    messages, bundle = _messages_of(dgram)
    elements, types = _WARNINGS.take()
    if types:
        raise Drop("malformed", f"{types} argument(s) of an unknown OSC type")
    if elements and counts is not None:
        counts.skipped += elements
        for _ in range(elements):
            counts.drop("malformed", "a bundle element that is not OSC")
    return messages, bundle


def _messages_of(dgram: bytes) -> tuple[list[osc_message.OscMessage], bool]:
    if not isinstance(dgram, (bytes, bytearray)) or not dgram:
        raise Drop("malformed", "an empty datagram")
    dgram = bytes(dgram)
    if len(dgram) > MAX_DATAGRAM:
        raise Drop("malformed", f"a datagram of {len(dgram)} bytes")
    try:
        if osc_bundle.OscBundle.dgram_is_bundle(dgram):
            out: list[osc_message.OscMessage] = []
            stack = [iter(osc_bundle.OscBundle(dgram))]
            while stack:  # depth first, in order, without recursion
                item = next(stack[-1], None)
                if item is None:
                    stack.pop()
                elif isinstance(item, osc_bundle.OscBundle):
                    stack.append(iter(item))
                else:
                    out.append(item)
            return out, True
        if osc_message.OscMessage.dgram_is_message(dgram):
            message = osc_message.OscMessage(dgram)
            message.params  # noqa: B018 - parsed lazily in some versions
            return [message], False
    except RecursionError:
        raise Drop("malformed", "bundles nested too deeply") from None
    except Exception as exc:  # python-osc's ParseError, and whatever garbage provokes
        raise Drop("malformed", f"not OSC ({type(exc).__name__})") from None
    raise Drop("malformed", "not an OSC message or bundle")


def number(value, what: str) -> float:
    """An OSC argument as a finite float (int, int64, float or double; not a bool)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise Drop("bad_arguments", f"{what}: expected a number, got {type(value).__name__}")
    try:
        out = float(value)
    except OverflowError:
        raise Drop("out_of_range", f"{what}: a number too large") from None
    if not math.isfinite(out):
        raise Drop("not_finite", f"{what}: {out}")
    return out


def bounded(value, what: str, limit: float) -> float:
    """``number``, and within -limit..limit."""
    out = number(value, what)
    if abs(out) > limit:
        raise Drop("out_of_range", f"{what}: {out:g} beyond +-{limit:g}")
    return out


def text(value, what: str) -> str:
    if not isinstance(value, str):
        raise Drop("bad_arguments", f"{what}: expected a string, got {type(value).__name__}")
    return value


class FrameClock:
    """Judges frame times: each must be after the last one accepted."""

    def __init__(self):
        self.last: float | None = None

    def check(self, t: float | None, counts: Counts) -> None:
        """Raise ``Drop`` if ``t`` goes back (or repeats); None (no time) passes."""
        if t is None:
            return
        if self.last is not None:
            if t < self.last - RESTART_GAP:
                counts.restarts += 1  # the sender started again: a new stream
            elif t < self.last:
                raise Drop("out_of_order", f"time {t:.4f} s before {self.last:.4f} s")
            elif t == self.last:
                raise Drop("stale", f"time {t:.4f} s repeated")
        self.last = t


def frame_time(value, what: str = "time") -> float:
    t = number(value, what)
    if not 0.0 <= t <= MAX_TIME:
        raise Drop("out_of_range", f"{what}: {t:g} s is not 0..{MAX_TIME:g}")
    return t


class Decoder:
    """A format's decoder: ``feed`` a datagram, get the frames it completes (often
    one, or none); every problem is counted in ``counts``, never raised."""

    format = ""
    default_port = 0

    def __init__(self):
        self.counts = Counts()
        self.clock = FrameClock()

    def feed(self, dgram: bytes) -> list[Frame]:
        counts = self.counts
        counts.packets += 1
        try:
            messages, bundle = messages_of(dgram, counts)
        except Drop as drop:
            counts.drop(drop.reason, drop.detail)
            return []
        frames: list[Frame] = []
        for message in messages:
            counts.messages += 1
            ignored = counts.ignored
            try:
                address = message.address
                if not isinstance(address, str):
                    raise Drop("malformed", "no address")
                frame = self.message(address, list(message.params))
            except Drop as drop:
                counts.drop(drop.reason, drop.detail)
                continue
            if counts.ignored == ignored:
                counts.accepted += 1
            if frame is not None:
                self._accept(frame, frames)
        if bundle:
            self._accept(self.bundle_end(), frames)
        return frames

    def _accept(self, frame: Frame | None, frames: list[Frame]) -> None:
        if frame is None:
            return
        if frame.time is not None and frame.time == self.clock.last and self.novel(frame):
            self.counts.continued += 1  # the same frame, its next part
            self.committed()
            self.counts.frames += 1
            frames.append(self.finish(frame))
            return
        try:
            self.clock.check(frame.time, self.counts)
        except Drop as drop:
            self.counts.drop(drop.reason, drop.detail)
            self.rejected()
            return
        self.committed()
        self.counts.frames += 1
        frames.append(self.finish(frame))

    # -- what a format fills in
    def message(self, address: str, args: list) -> Frame | None:
        """Judge one message; a Frame when it completes one. Raise Drop to drop it."""
        raise NotImplementedError

    def bundle_end(self) -> Frame | None:
        """The frame a bundle's end completes, if any."""
        return None

    def rejected(self) -> None:
        """The frame just made was dropped (its time): forget what it staged."""

    def novel(self, frame: Frame) -> bool:
        """Whether a frame with the last one's time brings something new (then it goes
        on with that frame; else it is ``stale``). A format whose frames come whole
        says no."""
        return False

    def committed(self) -> None:
        """The frame just made was accepted: keep what it staged."""

    def finish(self, frame: Frame) -> Frame:
        """The accepted frame as handed out (e.g. with its points computed)."""
        return frame
