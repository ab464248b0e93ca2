"""A live motion-capture source: an OSC server on its own thread, frames into a LiveQueue.

    source = OscSource("vmc", port=39539, retargeter=rt)   # bound to 127.0.0.1
    source.start()
    ...each frame of the window or of a headless loop:
    for event in source.drain():
        session.handle(event)                          # recorded at the step it acts

python-osc's UDP server receives on a thread; each datagram is decoded
(``puppet.mocap.formats``) and every frame becomes the values of one ``channels``
event: the Retargeter's channels of the frame's points (VMC, MediaPipe), or the
channels sent (puppet's address). Events go through a ``LiveQueue`` (checked and
counted there too), and ``drain`` hands what came since the last frame over as one
event (the frames of one drain act at the same step, the latest value of a channel
wins, so merging them changes nothing but the log's size).

Tracking lost (no fresh sample for ``LOST_AFTER``, 0.25 s): judged twice, for two
purposes. The interface's tracking judges it in simulated time (``tracking.lost_after``:
no ``channels`` sample for that long and it lets go of the joints, so the keys drive
them, until samples come again); that needs no event, so it holds the same in a replay,
a rewind or a slowed-down window. The source judges it in wall time, for the performer:
``tracking`` goes False and the status line (HUD, ``puppet mocap listen``) says
``LOST`` when no sample has come for 0.25 s; nothing of it goes into the log.
"""

from __future__ import annotations

import collections
import math
import select
import socket
import threading
import time
from collections.abc import Callable

from puppet.data.errors import UsageError
from puppet.input.live import LiveQueue
from puppet.interface import events as ev
from puppet.mocap.formats import LOCALHOST, decoder
from puppet.mocap.osc import Frame

LOST_AFTER = 0.25  # seconds without a fresh sample: tracking is lost
RATE_WINDOW = 1.0  # seconds of arrivals the rate is measured over
RECEIVE_BUFFER = 4 << 20  # bytes of datagrams the socket holds until the thread reads them
MAX_DATAGRAM = 65535  # bytes: the largest UDP datagram
MAX_BACKLOG = 256  # datagrams read in one go before they are decoded (then the next go)


class OscSource:
    """Receives one format on ``host:port`` (default 127.0.0.1 and the format's port)."""

    def __init__(self, fmt: str, host: str = LOCALHOST, port: int | None = None,
                 retargeter=None, lost_after: float = LOST_AFTER,
                 clock: Callable[[], float] = time.perf_counter, guard=None,
                 smoother=None):
        self.decoder = decoder(fmt)
        self.format = fmt
        self.retargeter = retargeter
        self.guard = guard  # judges points and channels against the figure (guard.py)
        self.smoother = smoother  # filters what the guard kept (smoothing.py)
        self.host = host
        self.port = self.decoder.default_port if port is None else port
        self.lost_after = lost_after
        self.clock = clock
        self.queue = LiveQueue(f"mocap {fmt}")
        self._lock = threading.Lock()
        self._server = None
        self._thread: threading.Thread | None = None
        self.last_arrival: float | None = None  # clock time of the last sample posted
        self.last_frame: float | None = None  # ... of the last frame decoded (mapped or not)
        self.unmapped = 0  # frames that gave no channels (no mapping, or no point it reads)
        self.unmapped_reason = ""  # why the first of them gave none (``reasons``)
        self.last_names: tuple[str, ...] = ()  # the points (or channels) of the last frame
        self.skipped = 0  # pose frames a newer one in the same backlog made stale
        self._stop = threading.Event()
        self.lost_count = 0
        self.fresh = False  # a sample came within lost_after (wall time) of the last drain
        self._arrivals: collections.deque = collections.deque()
        self._times: list = []  # (sender's time, arrival) of the frames posted, until drained
        self.drained_times: list = []  # ... of the frames the last drain handed over

    # -- the receiving side (the server's thread, or a test calling it directly)
    def receive(self, dgram: bytes, arrival: float | None = None) -> int:
        """Decode one datagram; post its frames. Returns how many were posted."""
        return self.receive_many([dgram], arrival)

    def receive_many(self, dgrams: list[bytes], arrival: float | None = None) -> int:
        """Decode datagrams that came together (the socket's backlog) and post the newest
        of their frames: a frame of points (a whole pose) makes the ones before it stale,
        so only it is retargeted (the others are counted in ``skipped``); channel frames
        (which may carry a few channels each) are all taken. What a drain hands over is
        the same as if each had been posted: the newest value of each channel."""
        arrival = self.clock() if arrival is None else arrival
        with self._lock:
            frames = [f for dgram in dgrams for f in self.decoder.feed(dgram)]
            if frames and frames[-1].points:
                newest = [f for f in frames if f.channels] + frames[-1:]
                self.skipped += len(frames) - len(newest)
                self._arrivals.extend([arrival] * (len(frames) - len(newest)))
                frames = newest
            posted = 0
            for frame in frames:
                self.last_names = tuple(frame.points or frame.channels)
                self.last_frame = arrival
                self._arrivals.append(arrival)
                guard = self.guard
                if guard is not None and frame.points and guard.pose is not None:
                    how = guard.pose.judge(frame.points, arrival)
                    if how == "drop":
                        continue
                    if how == "rejoin" and self.retargeter is not None:
                        self.retargeter.rebase()  # the root jumped: no travel, a new floor
                values = self._channels(frame)
                if not values:
                    self.unmapped += 1
                    if not self.unmapped_reason and self.retargeter is not None:
                        self.unmapped_reason = self._unmapped_why(frame)
                    continue
                if guard is not None:
                    values = guard.channels.judge(values, arrival)
                    if not values:  # every channel absurd: no sample
                        continue
                if self.smoother is not None:  # on the sender's clock if it sends one
                    values = self.smoother.apply(
                        values, frame.time if frame.time is not None else arrival)
                if self.queue.post_merged(ev.channels(values)):
                    posted += 1
                    self.last_arrival = arrival
                    self._times.append((frame.time, arrival))
            while self._arrivals and self._arrivals[0] < arrival - RATE_WINDOW:
                self._arrivals.popleft()
        return posted

    def _channels(self, frame: Frame) -> dict[str, float]:
        if frame.channels:
            return dict(frame.channels)
        if not frame.points or self.retargeter is None:
            return {}
        try:  # a channel the mapping cannot make this frame (not finite) is left out
            return {str(k): v for k, v in ((k, float(v)) for k, v in
                                          self.retargeter.channels(frame.points).items())
                    if math.isfinite(v)}
        except Exception as exc:  # a live stream never takes the frame loop down
            self.decoder.counts.last_problem = f"mapping failed: {type(exc).__name__}: {exc}"
            return {}

    def _unmapped_why(self, frame: Frame) -> str:
        """Why a frame of points gave no channel through the retargeter."""
        problem = self.decoder.counts.last_problem
        if problem.startswith("mapping failed"):
            return problem
        missing = sorted(set(self.retargeter.point_names) - set(frame.points))
        if missing:
            return (f"the frame lacks {len(missing)} of the {len(self.retargeter.point_names)} "
                    f"points the mapping reads ({', '.join(missing[:4])}"
                    f"{'...' if len(missing) > 4 else ''})")
        return "the mapping made no finite channel of the frame's points"

    def reasons(self) -> list[tuple[str, str]]:
        """(kind, what the first of its drops said) for each kind of drop seen so far,
        in ``DROP_REASONS`` order, then ``unmapped`` (with a mapping)."""
        from puppet.mocap.guard import GUARD_REASONS
        from puppet.mocap.osc import DROP_REASONS

        with self._lock:
            first = dict(self.decoder.counts.first_detail)
            out = [(r, first[r]) for r in DROP_REASONS if r in first]
            if self.guard is not None:
                judged = self.guard.tally.first_detail
                out += [(r, judged[r]) for r in GUARD_REASONS if r in judged]
            if self.unmapped and self.unmapped_reason:
                out.append(("unmapped", self.unmapped_reason))
        return out

    # -- the frame loop's side
    def drain(self, sim_time: float | None = None, wall: float | None = None) -> list[dict]:
        """What arrived since the last drain as (at most) one ``channels`` event.
        ``sim_time`` (what the window passes every source) is not used: a live stream
        goes by the wall clock (``wall``, default ``clock()``), which also says whether
        the stream is lost (``tracking``)."""
        now = self.clock() if wall is None else wall
        with self._lock:  # the events and the arrival of the last of them, together
            events = self.queue.drain()
            last = self.last_arrival
            self.drained_times, self._times = self._times, []
        values: dict[str, float] = {}
        for event in events:
            values.update(event["values"])
        out = [ev.channels(values)] if values else []
        if values:
            self.fresh = True
        if self.fresh and last is not None and now - last > self.lost_after:
            self.fresh = False  # the status says LOST; the tracking judges it in sim time
            self.lost_count += 1
        return out

    def feed(self, session) -> int:
        events = self.drain(session.time)
        for event in events:
            session.handle(event)
        return len(events)

    @property
    def tracking(self) -> bool:
        return self.fresh

    def status(self, now: float | None = None) -> str:
        """One line for the HUD and ``puppet mocap listen``."""
        now = self.clock() if now is None else now
        with self._lock:
            c = self.decoder.counts
            recent = sum(1 for a in self._arrivals if a >= now - RATE_WINDOW)
            last = self.last_frame
            text = (f"mocap {self.format} {self.where_text()}: {c.packets} packets, "
                    f"{c.frames} frames, {recent / RATE_WINDOW:.0f} Hz")
            text += ", no sample yet" if last is None else f", last {now - last:.2f} s ago"
            if self.lost_count and not self.fresh:
                text += ", LOST"
            text += f", {c.drops_text()}"
            if c.no_pose:
                text += f", {c.no_pose} no pose"
            if c.continued:
                text += f", {c.continued} continued"
            judged = self.guard.tally.text() if self.guard is not None else ""
            if judged:
                text += f", {judged}"
            dropped = self.queue.dropped_bad + self.queue.dropped_overflow
            if dropped:
                text += f", {dropped} events refused"
            if self.unmapped and self.retargeter is not None:  # listen without a mapping
                text += f", {self.unmapped} unmapped"
        return text

    def where_text(self, short: bool = False) -> str:
        """Where the stream comes to: ``HOST:PORT`` (short: ``:PORT``)."""
        return f":{self.port}" if short else f"{self.host}:{self.port}"

    def listening_line(self) -> str:
        """What ``play --mocap`` says when the source has started."""
        return f"mocap: listening for {self.format} on udp://{self.host}:{self.port}"

    def hud_line(self, now: float | None = None) -> str:
        """The status, short enough for the HUD: rate, sample age, drops."""
        now = self.clock() if now is None else now
        with self._lock:
            c = self.decoder.counts
            recent = sum(1 for a in self._arrivals if a >= now - RATE_WINDOW)
            last = self.last_frame
            judged = self.guard.tally.text() if self.guard is not None else ""
        age = "waiting" if last is None else f"{now - last:.2f} s ago"
        text = f"mocap {self.format} {self.where_text(True)}  {recent / RATE_WINDOW:.0f} Hz  {age}"
        if self.lost_count and not self.fresh:
            text += "  LOST"
        return f"{text}  {c.drops_text()}" + (f"  {judged}" if judged else "")

    # -- the server
    def start(self) -> "OscSource":
        """Listen on a thread of its own, which reads every datagram the socket holds
        at once and decodes them (``receive_many``): the frame loop never decodes, and
        a backlog built while the interpreter was busy elsewhere is caught up in one go
        instead of datagram by datagram behind the stream."""
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            sock.bind((self.host, self.port))
        except OSError as exc:
            sock.close()
            raise UsageError(f"cannot listen on udp://{self.host}:{self.port}: "
                             f"{exc.strerror or exc}") from None
        self.port = sock.getsockname()[1]  # port 0: the one the system chose
        try:  # room for a burst while the frame loop holds the interpreter (the system
            # may cap it): datagrams beyond the buffer are lost before anyone sees them
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER)
        except OSError:
            pass
        sock.setblocking(False)
        self._server = sock
        self._stop.clear()
        self._thread = threading.Thread(target=self._serve, args=(sock,),
                                        name=f"mocap-{self.format}", daemon=True)
        self._thread.start()
        return self

    def _serve(self, sock: socket.socket) -> None:
        while not self._stop.is_set():
            try:
                ready, _, _ = select.select([sock], [], [], 0.05)
            except (OSError, ValueError):  # closed under us
                return
            if not ready:
                continue
            dgrams = []
            while len(dgrams) < MAX_BACKLOG:
                try:
                    dgrams.append(sock.recv(MAX_DATAGRAM))
                except (BlockingIOError, InterruptedError):
                    break
                except OSError:  # an ICMP error on some systems: the datagram is gone
                    break
            if dgrams:
                try:
                    self.receive_many(dgrams)
                except Exception as exc:  # noqa: BLE001 - a live stream never stops the app
                    self.decoder.counts.last_problem = f"{type(exc).__name__}: {exc}"

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
            self._thread = None
        if self._server is not None:
            self._server.close()
            self._server = None

    def __enter__(self) -> "OscSource":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.close()
