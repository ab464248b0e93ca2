"""How long a live sample takes from the network to the servo targets (``puppet bench``).

A loopback sender (a thread) streams frames at ``rate`` Hz, stamping each one's send
time (the frame's time in the stream says which frame it is); an ``OscSource`` receives
them on its thread; a 60 fps frame loop, paced like the window's, drains the source into
a Session and steps the physics. Two paths:

* ``puppet``: /puppet/channels frames (eight slow sinusoids) onto channel maps of the
  human figure; the targets are set when the maps run (``runtime.flush``, what
  ``advance`` does first);
* ``vmc``: the CMU walk as VMC bundles (``puppet mocap send``'s encoder), decoded with
  forward kinematics and retargeted (vmc-humanoid) on the source's thread, onto
  biped-mocap's KD tracking, which writes the targets on its control ticks: the time is
  taken after the frame's steps (an upper bound: the first tick comes sooner).

The headline is a frame's time from its send to the targets set from it: the loopback,
the wait for the source's thread, its decoding (and retargeting) there, the wait for the
loop's next frame and the session's handling. Under load the source's thread is what
falls behind: it reads the whole backlog the socket holds at once and decodes only the
newest pose (``OscSource.receive_many``), and the queue to the frame loop keeps at most
one frame (``queued_max``). A frame's latency from its arrival (decoded on the source's
thread) to the targets set from it is kept beside it; it holds the wait for the next
frame of the loop (up to one frame) and
the session's handling. The target, "within one frame at 60 fps": every sample acts at
the first frame of the loop after it arrives (``next_frame_pct`` 100), so its latency
is at most that frame's wait plus the handling (``processing``); in milliseconds that
is half a frame on average and, with the loop's own timing jitter, up to about one.
"""

from __future__ import annotations

import math
import socket
import threading
import time

FRAME_HZ = 60.0


def _puppet_path(rate: float):
    """(setup, source, encode(k, t) -> datagram, targets set at the flush?)"""
    from puppet.commands.bench.channels import channel_interface_text
    from puppet.data.catalog import load_character_named, setup_from_text
    from puppet.mocap import puppet_osc
    from puppet.mocap.source import OscSource

    biped, _ = load_character_named("biped")
    setup = setup_from_text(channel_interface_text(biped, "biped-track", count=8),
                            "<mocap-latency>")

    def encode(k: int, t: float) -> bytes:
        return puppet_osc.encode_frame(t, {f"c{i}": 0.9 * math.sin(2 * math.pi * 0.5 * t + i)
                                           for i in range(8)})
    return setup, OscSource("puppet", port=0), encode, True


def _vmc_path(rate: float):
    from puppet.commands.streams import source_for
    from puppet.data.catalog import ROOT, load_setup
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.send import encoder, load_bones

    clip = read_bvh(ROOT / "assets" / "mocap" / "cmu-131_01-walk.bvh")
    clip_encode = encoder(clip, "vmc", load_bones(ROOT / "assets" / "mocap" / "cmu-bones.yaml"))
    setup = load_setup("biped-mocap")

    def encode(k: int, t: float) -> bytes:
        return clip_encode(k % clip.frames, t)
    return setup, source_for("udp://127.0.0.1:0", "vmc", None, setup), encode, False


PATHS = {"puppet": _puppet_path, "vmc": _vmc_path}


def measure_latency(seconds: float = 3.0, rate: float = 120.0, path: str = "puppet") -> dict:
    """Stream ``seconds`` of frames over loopback into a Session (``path``: see above)."""
    from puppet.session import Session

    setup, source, encode, at_flush = PATHS[path](rate)
    session = Session(setup)
    steps_per_frame = max(1, round(1.0 / (FRAME_HZ * session.sim.dt)))
    sent: dict[int, float] = {}
    stop = threading.Event()
    latencies: list[float] = []  # arrival (decoded on the source's thread) -> targets set
    transit: list[float] = []  # send -> arrival: loopback and the source thread's wake-up
    waited: list[int] = []  # frames of the loop each sample waited (1: the next frame)
    processing: list[float] = []  # drain -> targets set (the session's handling)
    drains: list[float] = []  # when each earlier frame drained the source
    send_to_target: list[float] = []  # send -> targets set: everything on the way
    queued_max = 0  # the most channels events waiting at a drain (one: skip-to-newest)
    changed = 0
    with source:
        address = (source.host, source.port)

        def send() -> None:
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
                start = time.perf_counter()
                k = 0
                while not stop.is_set():
                    dgram = encode(k, k / rate)
                    sent[k] = time.perf_counter()
                    sock.sendto(dgram, address)
                    k += 1
                    wait = start + k / rate - time.perf_counter()
                    if wait > 0:
                        time.sleep(wait)

        sender = threading.Thread(target=send, name="latency-sender", daemon=True)
        sender.start()
        start = time.perf_counter()
        frame = 0
        servos = session.character.servos
        try:
            while time.perf_counter() - start < seconds:
                frame += 1
                wait = start + frame / FRAME_HZ - time.perf_counter()
                if wait > 0:
                    time.sleep(wait)
                before = [s.target for s in servos.values()]
                queued_max = max(queued_max, source.queue.pending())
                drain_at = time.perf_counter()
                for event in source.drain(session.time):
                    session.handle(event)
                if at_flush:
                    session.runtime.flush()  # what advance() does first: the targets set
                    done = time.perf_counter()
                session.advance(steps_per_frame)
                if not at_flush:
                    done = time.perf_counter()  # the tracker wrote them on its ticks
                if source.drained_times:
                    if [s.target for s in servos.values()] != before:
                        changed += 1
                    for t, arrival in source.drained_times:
                        k = round(t * rate)
                        if k in sent:
                            latencies.append(done - arrival)
                            send_to_target.append(done - sent[k])
                            transit.append(arrival - sent[k])
                            # the drains since it arrived (1: it acted at the next frame)
                            waited.append(1 + sum(1 for d in drains[-3:] if d > arrival))
                            processing.append(done - drain_at)
                drains.append(drain_at)
        finally:
            stop.set()
            sender.join(timeout=2.0)
        counts = source.decoder.counts
        unmapped = source.unmapped

    def pct(values: list[float], p: float) -> float:
        values = sorted(values)
        return values[min(len(values) - 1, int(p * len(values)))] * 1e3 if values \
            else float("nan")

    return {"path": path, "samples": len(latencies), "frames": frame, "rate_hz": rate,
            "frame_hz": FRAME_HZ, "send_median_ms": pct(send_to_target, 0.5),
            "send_p99_ms": pct(send_to_target, 0.99), "queued_max": queued_max,
            "skipped": source.skipped, "median_ms": pct(latencies, 0.5),
            "p99_ms": pct(latencies, 0.99), "max_ms": pct(latencies, 1.0),
            "transit_median_ms": pct(transit, 0.5), "transit_p99_ms": pct(transit, 0.99),
            "processing_median_ms": pct(processing, 0.5),
            "processing_max_ms": pct(processing, 1.0),
            "next_frame_pct": 100.0 * sum(1 for w in waited if w == 1) / max(1, len(waited)),
            "targets_changed": changed, "dropped": counts.total_dropped, "unmapped": unmapped,
            "frame_ms": 1e3 / FRAME_HZ}
