"""The live path over loopback: an OscSource on a thread, frames into channels events,
tracking lost after 0.25 s, a real-time headless take recorded and replayed to the
same hash with no network; the command line's errors."""

from __future__ import annotations

import socket
import threading
import time

import pytest
from helpers import ListenedPort

from puppet.app.live import run_live
from puppet.commands import main
from puppet.commands.bench.channels import channel_interface_text
from puppet.data.catalog import load_character_named, load_setup
from puppet.mocap import puppet_osc
from puppet.mocap.source import LOST_AFTER, OscSource
from puppet.timeline.log import read_log
from puppet.timeline.replay import replay


class FakeClock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


def _cat_channels(tmp_path):
    cat, _ = load_character_named("cat")
    path = tmp_path / "cat-channels.yaml"
    path.write_text(channel_interface_text(cat, "cat-flat", count=4))
    return str(path)


def _sender(port, seconds, rate=120.0, stop=None, values_at=None):
    """Send /puppet/channels c0..c3 (slow sinusoids; or ``values_at(k)``) at ``rate`` Hz
    for ``seconds`` to ``port`` (a number, or a ListenedPort to wait for). The thread's
    ``sent[0]`` counts the datagrams sent so far."""
    import math

    sent = [0]

    def run():
        nonlocal port
        if not isinstance(port, int):
            port = port.wait()
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            start = time.perf_counter()
            k = 0
            while time.perf_counter() - start < seconds and not (stop and stop.is_set()):
                t = k / rate
                values = ({f"c{i}": 0.9 * math.sin(2 * math.pi * 0.7 * t + i) for i in range(4)}
                          if values_at is None else values_at(k))
                sock.sendto(puppet_osc.encode_frame(t, values), ("127.0.0.1", port))
                k += 1
                sent[0] = k
                time.sleep(max(0.0, start + k / rate - time.perf_counter()))
    thread = threading.Thread(target=run, daemon=True)
    thread.sent = sent
    thread.start()
    return thread


# A live take runs on the wall clock, so what a busy machine delivers in it varies: the
# sender (a thread of this process) sends fewer frames, the receiving thread decodes
# them later, the live loop draws fewer frames. So the live tests hold a take to what
# was delivered (issue 32: the suite holds at a load of 8 on 2 cores): every frame sent
# before the take ended is received (waiting for the receiving thread as long again as
# the take took), none dropped, and a channels event in the log for (about) every drawn
# frame that had a new one (at a load of 20 on 2 cores a biped take drew 3 frames).
MIN_FRAMES = 20  # frames a take must receive at all, however loaded the machine


class Take:
    """What a live take delivered: ``on_frame`` for ``run_live`` (the frames drawn, and
    how many of them had a new frame from the source), ``ended`` after it."""

    def __init__(self, source):
        self.source, self.start = source, time.perf_counter()
        self.drawn = self.fresh = self.seen = 0

    def on_frame(self, session) -> None:
        self.drawn += 1
        frames = self.source.decoder.counts.frames
        self.fresh += frames > self.seen
        self.seen = frames

    def check(self, sent_by_end: int, streamed: int) -> None:
        took = time.perf_counter() - self.start
        counts = self.source.decoder.counts
        deadline = time.perf_counter() + took + 1.0  # the machine's pace, not a constant
        while counts.frames < sent_by_end and time.perf_counter() < deadline:
            time.sleep(0.01)
        assert counts.frames >= max(MIN_FRAMES, sent_by_end), (counts, sent_by_end, took)
        assert counts.total_dropped == 0, counts
        # a loaded machine draws few frames (each advances the physics further): as
        # many events as drawn frames that had a new one, give or take a merge
        assert self.fresh >= 1 and streamed >= 0.5 * self.fresh, (streamed, self.fresh)


def test_a_source_turns_frames_into_one_channels_event_per_drain_and_counts_drops():
    clock = FakeClock()
    source = OscSource("puppet", clock=clock)  # not started: fed directly
    source.receive(puppet_osc.encode_frame(0.0, {"a": 1.0, "b": 2.0}))
    source.receive(puppet_osc.encode_frame(0.01, {"a": 3.0}))
    source.receive(b"not osc")
    source.receive(puppet_osc.encode_frame(0.005, {"a": 9.0}))  # back in time
    events = source.drain()
    assert events == [{"type": "channels", "values": {"a": 3.0, "b": 2.0}}]
    assert source.drain() == []
    status = source.status()
    assert "4 packets, 2 frames" in status and "2 dropped" in status
    assert "1 malformed" in status and "1 out_of_order" in status


def test_tracking_is_lost_after_a_quarter_second_without_a_sample_and_comes_back():
    clock = FakeClock()
    source = OscSource("puppet", clock=clock)
    source.receive(puppet_osc.encode_frame(0.0, {"a": 1.0}))
    assert source.drain()[0]["values"] == {"a": 1.0} and source.tracking
    clock.now += LOST_AFTER - 0.01
    assert source.drain() == [] and source.tracking
    clock.now += 0.02
    assert source.drain() == []  # nothing goes into the log: the tracking judges itself
    assert not source.tracking and "LOST" in source.status() and "LOST" in source.hud_line()
    source.receive(puppet_osc.encode_frame(1.0, {"a": 2.0}))
    assert source.drain()[0]["values"] == {"a": 2.0}
    assert source.tracking and "LOST" not in source.status() and source.lost_count == 1


def test_points_go_through_the_retargeter_and_frames_it_cannot_map_are_counted():
    from puppet.mocap import mediapipe

    class Halves:  # a stand-in mapping: the left hip's height, halved (and a NaN)
        point_names = {"left_hip"}

        def channels(self, points):
            if "left_hip" not in points:
                return {}
            return {"hip": points["left_hip"][1] / 2, "broken": float("nan")}

    source = OscSource("mediapipe", retargeter=Halves())
    source.receive(mediapipe.encode_frame(None, {"left_hip": (0.0, 0.8, 0.0)}))
    source.receive(mediapipe.encode_frame(None, {"nose": (0.0, 1.0, 0.0)}))
    assert source.drain()[0]["values"] == {"hip": pytest.approx(0.4)}
    assert source.unmapped == 1 and "1 unmapped" in source.status()


def test_a_live_take_over_loopback_replays_to_the_recorded_hash(tmp_path):
    setup = load_setup(_cat_channels(tmp_path))
    record = tmp_path / "take.jsonl"
    with OscSource("puppet", port=0) as source:  # the system picks a free port
        stop = threading.Event()
        take = Take(source)
        sender = _sender(source.port, seconds=60, stop=stop)
        session = run_live(setup, [source], seconds=1.5, record=record, slowdown=1.0,
                           on_frame=take.on_frame)
        sent_by_end = sender.sent[0]  # ~180 (120 Hz for 1.5 s) on an idle machine
        stop.set()
        sender.join()
        log = read_log(record)
        streamed = [e for e in log.events if e.event["type"] == "channels"]
        take.check(sent_by_end, len(streamed))  # about one event a drawn frame
    assert all(set(e.event["values"]) <= {"c0", "c1", "c2", "c3"} for e in streamed)
    assert log.end_hash == session.sim.state_hash()
    result = replay(record)  # headless, no network
    assert result.final_hash == log.end_hash
    # the stream moved the joints: the hash could tell a broken path
    start = session.character.spec.start.joints
    import math
    moved = [abs(math.degrees(session.character.servos[j].target) - start.get(j, 0.0))
             for j in session.character.servos]
    assert max(moved) > 2.0


def test_the_walk_clip_streamed_over_vmc_drives_the_mocap_figure_and_replays(tmp_path):
    """``puppet mocap send`` (VMC, the CMU walk) -> the shipped vmc-humanoid mapping ->
    biped-mocap's KD tracking, recorded live and replayed headless to the same hash."""
    from puppet.commands.streams import source_for
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.send import encoder, load_bones, stream

    clip = read_bvh("assets/mocap/cmu-131_01-walk.bvh")
    encode = encoder(clip, "vmc", load_bones("assets/mocap/cmu-bones.yaml"))
    setup = load_setup("biped-mocap")
    source = source_for("udp://127.0.0.1:0", "vmc", None, setup)
    record = tmp_path / "vmc-take.jsonl"
    sent = [0]
    with source:
        take = Take(source)
        stop = threading.Event()
        sender = threading.Thread(target=stream, args=(encode, 300, clip.frame_time,
                                                       (source.host, source.port)),
                                  kwargs={"stop": stop,
                                          "on_sent": lambda n: sent.__setitem__(0, n)},
                                  daemon=True)
        sender.start()
        try:
            session = run_live(setup, [source], seconds=1.5, record=record, slowdown=1.0,
                               on_frame=take.on_frame)
        finally:
            sent_by_end = sent[0]  # ~180 on an idle machine
            stop.set()
            sender.join()
        log = read_log(record)
        streamed = [e.event["values"] for e in log.events if e.event["type"] == "channels"]
        take.check(sent_by_end, len(streamed))
    assert source.unmapped == 0
    assert {"hip_near", "knee_far", "root.x", "root.y"} <= set(streamed[-1])
    assert replay(record).final_hash == log.end_hash == session.sim.state_hash()
    assert session.character.upright()


def test_play_mocap_headless_records_and_replay_checks(tmp_path, capsys, monkeypatch):
    interface = _cat_channels(tmp_path)
    record = tmp_path / "cli.jsonl"
    listened = ListenedPort(monkeypatch)
    stop = threading.Event()
    sender = _sender(listened, seconds=3.0, stop=stop)
    try:
        code = main(["play", interface, "--headless", "--seconds", "0.8", "--record",
                     str(record), "--mocap", "udp://127.0.0.1:0",
                     "--mocap-format", "puppet", "--slowdown", "1"])
    finally:
        stop.set()
        sender.join()
    out = capsys.readouterr().out
    assert code == 0, out
    port = listened.port
    assert f"mocap puppet 127.0.0.1:{port}:" in out and "recorded" in out
    assert main(["replay", str(record), "--headless", "--check"]) == 0


def test_a_live_take_that_blows_up_says_so_on_stderr_and_exits_3(capsys, monkeypatch):
    """A performer's wild stream (uniform +-180 deg on every channel at 120 Hz) into
    biped-mocap, with the guard that judges live samples turned off (it drops most of
    them: test_mocap_guard), blows the simulation up: the headless take says each
    recovery, as a clip run does, not only exit 3."""
    import random

    import puppet.mocap.guard

    monkeypatch.setattr(puppet.mocap.guard, "rules_for", lambda setup, mapping=None: {})
    rng = random.Random(7)
    names = ("hip_near", "hip_far", "knee_near", "knee_far", "root.x", "root.y", "root.angle")
    listened = ListenedPort(monkeypatch)
    stop = threading.Event()
    sender = _sender(listened, seconds=5.0, stop=stop,
                     values_at=lambda k: {n: rng.uniform(-180.0, 180.0) for n in names})
    try:
        code = main(["play", "biped-mocap", "--headless", "--seconds", "0.6", "--no-record",
                     "--mocap", "udp://127.0.0.1:0", "--mocap-format", "puppet",
                     "--slowdown", "1"])
    finally:
        stop.set()
        sender.join()
    captured = capsys.readouterr()
    assert code == 3, captured.out
    lines = captured.err.splitlines()
    assert lines and all(line.startswith("puppet play: the simulation blew up at t=")
                         for line in lines), captured.err


@pytest.mark.parametrize("argv, words", [
    (["--mocap", "udp://127.0.0.1:39599", "--mapping", "cmu-131"],
     "reads points a vmc stream never sends (Chest2, LeftAnkle, LeftElbow, LeftHip...); "
     "expected Unity humanoid bone names (e.g. the shipped vmc-humanoid)"),
    (["--mocap", "udp://127.0.0.1:39599", "--mocap-format", "puppet", "--mapping", "cmu-131"],
     "a puppet stream sends channels: it needs no --mapping"),
    (["--mocap", "udp://example.org:1", "--mocap-format", "puppet"], "not an IP address"),
    (["--mocap", "tcp://127.0.0.1:1", "--mocap-format", "puppet"], "only udp://"),
    (["--mocap", "udp://127.0.0.1:1", "--mocap-format", "puppet", "--input", "luxo-hop"],
     "--mocap udp://... goes without --input"),
])
def test_play_mocap_mistakes_are_one_line_errors(argv, words, capsys):
    code = main(["play", "luxo-mouse", "--headless", *argv])
    err = capsys.readouterr().err
    assert code == 2 and words in err and err.count("\n") == 1


def test_a_port_in_use_is_a_one_line_error(capsys):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as held:
        held.bind(("127.0.0.1", 0))
        port = held.getsockname()[1]
        code = main(["play", "luxo-mouse", "--headless", "--mocap",
                     f"udp://127.0.0.1:{port}", "--mocap-format", "puppet"])
    err = capsys.readouterr().err
    assert code == 2 and f"cannot listen on udp://127.0.0.1:{port}" in err


def test_listen_prints_what_arrives(capsys, monkeypatch):
    listened = ListenedPort(monkeypatch)
    stop = threading.Event()
    sender = _sender(listened, seconds=0.8, stop=stop)  # stops before listen does: LOST
    try:
        assert main(["mocap", "listen", "--format", "puppet", "--port", "0",
                     "--seconds", "2.2"]) == 0
    finally:
        stop.set()
        sender.join()
    out = capsys.readouterr().out
    port = listened.port
    assert f"listening for puppet on udp://127.0.0.1:{port}" in out
    assert "4 named: c0, c1, c2, c3" in out and "channels: c0=" in out
    assert "0 dropped" in out
    assert "LOST" in out.splitlines()[-1]  # the stream stopped over a second ago


def test_listen_says_why_once_per_kind_of_drop(capsys, monkeypatch):
    """A MediaPipe sender, garbage and VMC frames with only the hips, to a vmc listen
    through vmc-humanoid: the counts every second, and the first reason of each kind
    once (the foreign address names the format that takes it)."""
    from puppet.mocap import mediapipe, vmc

    listened = ListenedPort(monkeypatch)
    stop = threading.Event()

    def send():
        port = listened.wait()
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            k = 0
            while not stop.is_set() and k < 120:
                for dgram in (mediapipe.encode_frame(k / 60, {"nose": (0.0, 1.0, 0.0)}), b"xyz",
                              vmc.encode_frame(k / 60, {"Hips": ((0, 1, 0), (0, 0, 0, 1))})):
                    sock.sendto(dgram, ("127.0.0.1", port))
                k += 1
                time.sleep(1 / 60)
    sender = threading.Thread(target=send, daemon=True)
    sender.start()
    try:
        assert main(["mocap", "listen", "--port", "0", "--mapping", "vmc-humanoid",
                     "--seconds", "2.2"]) == 0
    finally:
        stop.set()
        sender.join()
    out = capsys.readouterr().out
    assert " unknown_address" in out and " malformed" in out and " unmapped" in out
    reasons = [line for line in out.splitlines() if line.startswith("  ") and ": " in line
               and not line.startswith(("  channels", "  1 named"))]
    assert len(reasons) == 3, out  # each kind once (the counts go on every second)
    assert "  malformed: not an OSC message or bundle" in reasons
    assert ("  unknown_address: '/mediapipe/pose' is not a VMC address (a mediapipe address: "
            "listen --format mediapipe?)") in reasons
    unmapped = next(line for line in reasons if line.startswith("  unmapped: "))
    assert unmapped.startswith("  unmapped: the frame lacks 18 of the 19 points the mapping "
                               "reads (Chest, Head, LeftFoot, LeftHand...)"), out


def test_send_streams_a_clip_that_listen_counts(tmp_path, capsys):
    with OscSource("vmc", port=0) as source:
        start = time.perf_counter()
        code = main(["mocap", "send", "assets/mocap/cmu-131_01-walk.bvh", "--to",
                     f"udp://127.0.0.1:{source.port}", "--speed", "5", "-q"])
        assert code == 0
        # the receiving thread may lag on a busy machine (the socket holds 4 MB): wait
        # for it as long again as the send took, not a fixed time
        deadline = time.perf_counter() + (time.perf_counter() - start) + 1.0
        while source.decoder.counts.frames < 994 and time.perf_counter() < deadline:
            time.sleep(0.01)
        # UDP: a datagram can be lost if the receiving thread falls far behind; none is
        # here, and none may be dropped as bad
        assert source.decoder.counts.frames >= 950
        assert source.decoder.counts.total_dropped == 0
        assert len(source.last_names) == 22


def test_vmc_frames_through_vmc_humanoid_give_the_clips_channels_through_cmu_131():
    """The same walk, as BVH joints through cmu-131 and as VMC bones (sent, decoded,
    forward kinematics) through vmc-humanoid: the same channels, frame by frame, to
    float32 precision."""
    from puppet.data.catalog import find
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.retarget import Retargeter, load_mapping
    from puppet.mocap.send import encoder, load_bones
    from puppet.mocap.vmc import VmcDecoder

    clip = read_bvh("assets/mocap/cmu-131_01-walk.bvh")
    encode = encoder(clip, "vmc", load_bones("assets/mocap/cmu-bones.yaml"))
    live = Retargeter(load_mapping(find("mapping", "vmc-humanoid")))
    bvh = Retargeter(load_mapping(find("mapping", "cmu-131")))
    _, pos = clip.world_transforms()
    decoder = VmcDecoder()
    worst, names = 0.0, set()
    for k in range(0, 400):
        got = live.channels(decoder.feed(encode(k, k * clip.frame_time))[0].points)
        want = bvh.channels({n: pos[k, clip.index(n)] for n in bvh.point_names})
        assert set(got) == set(want)
        names |= set(got)
        worst = max(worst, max(abs(got[n] - want[n]) for n in got))
    assert worst < 1e-3  # degrees and metres
    assert {"hip_near", "knee_near", "root.x", "hand_far.y"} <= names


def test_a_stream_that_stops_is_lost_to_the_tracker_in_sim_time():
    """After the stream stops the source posts nothing more; biped-mocap's tracker goes
    LOST lost_after (0.25 s) of simulated time after the last frame, as a replay of
    the take would (the source's own LOST is for the status line only)."""
    from puppet.session import Session

    setup = load_setup("biped-mocap")
    session = Session(setup)
    clock = FakeClock()
    source = OscSource("puppet", clock=clock)  # puppet channels named as the mapping's
    for k in range(30):  # 0.25 s of 120 Hz frames, drained at 60 fps
        source.receive(puppet_osc.encode_frame(k / 120, {"hip_near": 10.0, "root.y": 0.93}))
        if k % 2:
            clock.now += 1 / 60
            for event in source.drain(session.time):
                session.handle(event)
            session.advance(8)
    tracker = session.runtime.tracker
    assert not tracker.lost
    clock.now += 0.3  # the stream stops
    assert source.drain(session.time) == [] and not source.tracking
    session.advance(round(0.2 / session.sim.dt))
    assert not tracker.lost  # 0.2 s of sim time since the last frame
    session.advance(round(0.1 / session.sim.dt))
    assert tracker.lost and "LOST" in tracker.status


def test_mediapipe_landmarks_through_mediapipe_pose_give_cmu_131s_limb_channels():
    """The walk sent as MediaPipe landmarks: knees and elbows (the same joint centres
    in both mappings) agree with cmu-131's to float32 precision; the trunk (hip to
    shoulder: MediaPipe has no spine) agrees on the standing frames, by its offsets."""
    from puppet.data.catalog import find
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.mediapipe import MediaPipeDecoder
    from puppet.mocap.retarget import Retargeter, load_mapping
    from puppet.mocap.send import encoder, load_bones

    clip = read_bvh("assets/mocap/cmu-131_01-walk.bvh")
    encode = encoder(clip, "mediapipe", load_bones("assets/mocap/cmu-bones.yaml"))
    live = Retargeter(load_mapping(find("mapping", "mediapipe-pose")))
    bvh = Retargeter(load_mapping(find("mapping", "cmu-131")))
    _, pos = clip.world_transforms()
    decoder = MediaPipeDecoder()
    limbs, trunk = 0.0, []
    for k in range(0, 300):
        got = live.channels(decoder.feed(encode(k, k * clip.frame_time))[0].points)
        want = bvh.channels({n: pos[k, clip.index(n)] for n in bvh.point_names})
        limbs = max(limbs, *(abs(got[n] - want[n]) for n in
                             ("knee_near", "knee_far", "elbow_near", "elbow_far")))
        if k < 100:
            trunk.append(got["root.angle"] - want["root.angle"])
    assert limbs < 1e-3
    assert abs(sum(trunk) / len(trunk)) < 0.5  # degrees, on average while standing


def test_the_window_drains_a_live_source_shows_its_status_and_records_it(tmp_path,
                                                                         monkeypatch):
    """The window with a live puppet stream (SDL's dummy driver, 90 frames, then
    QUIT): the take is recorded as channels events and replays to its hash; the HUD
    draws the source's line."""
    import pygame

    from puppet.app import hud, window

    frames = {"n": 0}
    real_get = pygame.event.get

    def fake_get(*args, **kw):
        real_get()
        frames["n"] += 1
        return [pygame.event.Event(pygame.QUIT)] if frames["n"] >= 90 else []

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    monkeypatch.setattr(pygame.mouse, "set_pos", lambda pos: None)
    drawn = []
    real_hud = hud.draw_hud

    def spy(surface, session, info, font, small):
        drawn.append(info.sources)
        return real_hud(surface, session, info, font, small)

    monkeypatch.setattr(hud, "draw_hud", spy)
    setup = load_setup(_cat_channels(tmp_path))
    record = tmp_path / "window.jsonl"
    with OscSource("puppet", port=0) as source:
        stop = threading.Event()
        sender = _sender(source.port, seconds=5.0, stop=stop)
        try:
            assert window.run_window(setup, 1.0, record=str(record), sources=[source]) == 0
        finally:
            stop.set()
            sender.join()
    log = read_log(record)
    assert sum(1 for e in log.events if e.event["type"] == "channels") > 20
    assert replay(record).final_hash == log.end_hash
    assert drawn and drawn[-1][0].startswith(f"mocap puppet :{source.port}  ")
    assert "0 dropped" in drawn[-1][0]
