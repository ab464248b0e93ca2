"""How long a live sample takes from the network to the servo targets (``puppet bench``).

A loopback sender (a thread) streams frames at ``rate`` Hz, stamping each one's send
time (the frame's time in the stream says which frame it is); an ``OscSource`` receives
them on its thread; a 60 fps frame loop, paced like the window's, drains the source into
a Session, applies the channel maps (``runtime.flush``: the servo targets are set) and
steps the physics. A frame's latency is from its send (just before its arrival: the
loopback adds tens of microseconds) to the flush that set the targets from it, so it
holds the wait for the next frame of the loop (up to one frame), the decoding and
mapping on the source's thread and the session's handling. The target, "within one
frame at 60 fps": every sample acts at the first frame of the loop after it arrives
(``next_frame_pct`` 100), so its latency is at most that frame's wait plus the
handling (``processing``, well under a millisecond); in milliseconds that is half a
frame on average and, with the loop's own timing jitter, up to about one frame.
"""

from __future__ import annotations

import math
import socket
import threading
import time

FRAME_HZ = 60.0


def _interface(scene: str = "biped-track"):
    from puppet.bench import channel_interface_text
    from puppet.data.catalog import load_character_named, setup_from_text

    biped, _ = load_character_named("biped")
    return setup_from_text(channel_interface_text(biped, scene, count=8), "<mocap-latency>")


def measure_latency(seconds: float = 3.0, rate: float = 120.0) -> dict:
    """Stream ``seconds`` of /puppet/channels frames over loopback into a Session."""
    from puppet.mocap import puppet_osc
    from puppet.mocap.source import OscSource
    from puppet.session import Session

    session = Session(_interface())
    steps_per_frame = max(1, round(1.0 / (FRAME_HZ * session.sim.dt)))
    sent: dict[int, float] = {}
    stop = threading.Event()
    latencies: list[float] = []  # arrival (decoded on the source's thread) -> targets set
    from_send: list[float] = []  # the sender's send -> targets set
    transit: list[float] = []  # send -> arrival: loopback and the source thread's wake-up
    waited: list[int] = []  # frames of the loop each sample waited (1: the next frame)
    processing: list[float] = []  # drain -> targets set (the session's handling)
    drains: list[float] = []  # when each earlier frame drained the source
    changed = 0
    with OscSource("puppet", port=0) as source:
        address = (source.host, source.port)

        def send() -> None:
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
                start = time.perf_counter()
                k = 0
                while not stop.is_set():
                    t = k / rate
                    values = {f"c{i}": 0.9 * math.sin(2 * math.pi * 0.5 * t + i)
                              for i in range(8)}
                    dgram = puppet_osc.encode_frame(t, values)
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
                drain_at = time.perf_counter()
                for event in source.drain(session.time):
                    session.handle(event)
                session.runtime.flush()  # what advance() does first: the targets are set
                done = time.perf_counter()
                if source.drained_times:
                    if [s.target for s in servos.values()] != before:
                        changed += 1
                    for t, arrival in source.drained_times:
                        k = round(t * rate)
                        if k in sent:
                            latencies.append(done - arrival)
                            # the drains since it arrived (1: it acted at the next frame)
                            waited.append(1 + sum(1 for d in drains[-3:] if d > arrival))
                            processing.append(done - drain_at)
                            from_send.append(done - sent[k])
                            transit.append(arrival - sent[k])
                drains.append(drain_at)
                session.advance(steps_per_frame)
        finally:
            stop.set()
            sender.join(timeout=2.0)
        counts = source.decoder.counts
    def pct(values: list[float], p: float) -> float:
        values = sorted(values)
        return values[min(len(values) - 1, int(p * len(values)))] * 1e3 if values \
            else float("nan")

    return {"samples": len(latencies), "frames": frame, "rate_hz": rate, "frame_hz": FRAME_HZ,
            "median_ms": pct(latencies, 0.5), "p99_ms": pct(latencies, 0.99),
            "max_ms": pct(latencies, 1.0), "send_median_ms": pct(from_send, 0.5),
            "send_p99_ms": pct(from_send, 0.99), "transit_median_ms": pct(transit, 0.5),
            "transit_p99_ms": pct(transit, 0.99), "processing_median_ms": pct(processing, 0.5),
            "processing_max_ms": pct(processing, 1.0),
            "next_frame_pct": 100.0 * sum(1 for w in waited if w == 1) / max(1, len(waited)),
            "targets_changed": changed,
            "dropped": counts.total_dropped, "frame_ms": 1e3 / FRAME_HZ}
