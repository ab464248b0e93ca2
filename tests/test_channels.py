"""Channel streams: many named values per event, from a live thread through the
LiveQueue into the Session, recorded as one log line each and replayed exactly."""

from __future__ import annotations

import math
import threading

import pytest
from helpers import session_of

from puppet.commands.bench.channels import channel_frames, channel_interface_text
from puppet.data.actions import ActionSpec
from puppet.data.catalog import load_character_named, load_setup
from puppet.input.live import LiveQueue
from puppet.interface import events as ev
from puppet.session import Session
from puppet.timeline.log import Recorder, read_log
from puppet.timeline.replay import replay


def _setup(tmp_path):
    cat, _ = load_character_named("cat")
    path = tmp_path / "channels.yaml"
    path.write_text(channel_interface_text(cat, "cat-flat"))
    return load_setup(str(path))


def test_a_120hz_stream_of_40_channels_for_60_s_replays_to_the_recorded_hash(tmp_path):
    session = Session(_setup(tmp_path))
    path = tmp_path / "stream.jsonl"
    frames = channel_frames(60 * 60)  # 60 s of 1/60 s frames, two 120 Hz samples each
    with Recorder(session, path):
        for batch in frames:
            for event in batch:
                session.handle(event)
            session.advance(8)
    log = read_log(path)
    assert len(log.events) == 2 * len(frames) == 7200  # one line per 40-value sample
    assert all(len(e.event["values"]) == 40 for e in log.events)
    result = replay(path)
    assert result.final_hash == log.end_hash == session.sim.state_hash()
    # the stream really drives the joints (so the hash could tell a broken path)
    start = session.character.spec.start.joints
    moved = [abs(math.degrees(session.character.servos[j].target) - start.get(j, 0.0))
             for j in session.character.servos]
    assert max(moved) > 5.0


def test_several_samples_at_one_step_write_what_the_last_one_says(tmp_path):
    setup = _setup(tmp_path)
    once, twice = Session(setup), Session(setup)
    a, b = channel_frames(2)[1]
    once.handle(b)
    twice.handle(a)
    twice.handle(b)
    once.advance(40)
    twice.advance(40)
    assert once.sim.state_hash() == twice.sim.state_hash()
    assert once.runtime.channels == twice.runtime.channels


def test_an_action_after_a_sample_at_the_same_step_wins_the_joint(tmp_path):
    session = Session(_setup(tmp_path))
    servo = next(iter(session.character.servos.values()))  # the joint channel c0 drives
    session.handle(ev.channels({"c0": 1.0}))
    session.runtime.flush()
    driven = servo.target
    session.handle(ev.channels({"c0": -1.0}))  # pending: acts before anything after it
    session.handle(ev.mouse(0.5, 0.5))  # an event after it: the sample acts first
    assert servo.target != driven
    session.handle(ev.channels({"c0": 1.0}))
    session.runtime.run_action(ActionSpec(set={servo.name: 3.0}), session.steps)
    session.advance(1)
    assert math.isclose(math.degrees(servo.target), 3.0)  # the later action won


def test_a_live_thread_posts_through_the_queue_and_the_take_replays_exactly(tmp_path):
    session = Session(_setup(tmp_path))
    queue = LiveQueue("mocap")
    samples = [e for batch in channel_frames(240) for e in batch]
    done = threading.Event()

    def producer():
        for event in samples:
            queue.post(event)
        queue.post({"type": "channels", "values": {"c0": float("nan")}})  # dropped
        queue.post({"type": "channels", "values": "garbage"})  # dropped
        done.set()

    path = tmp_path / "live.jsonl"
    with Recorder(session, path):
        thread = threading.Thread(target=producer)
        thread.start()
        while not done.is_set():
            queue.feed(session)  # the frame loop: drain, then step
            session.advance(8)
        thread.join()
        queue.feed(session)
        session.advance(8)
    assert queue.dropped_bad == 2 and "dropped" in queue.status()
    log = read_log(path)
    assert len(log.events) == len(samples)
    assert replay(path).final_hash == log.end_hash == session.sim.state_hash()


def deg(s) -> dict[str, float]:
    return {n: round(math.degrees(sv.target), 6) for n, sv in s.character.servos.items()}


LUXO_CHANNEL = """
name: t
description: a channel on the knee
character: luxo
maps:
  - {input: channel.k, joint: knee, from: [0, 1], to: [0, 60]}
"""


def test_a_channel_moves_its_joint_after_a_restore_and_after_a_rewind(tmp_path):
    s = session_of(tmp_path, LUXO_CHANNEL)
    s.handle(ev.channels({"k": 0.5}))
    s.advance(100)
    s.handle(ev.action("checkpoint"))
    s.handle(ev.channels({"k": 0.25}))
    s.advance(100)
    assert deg(s)["knee"] == pytest.approx(15)
    s.handle(ev.action("restore"))
    assert s.steps == 100 and deg(s)["knee"] == pytest.approx(30)
    s.handle(ev.channels({"k": 1.0}))
    s.advance(1)
    assert deg(s)["knee"] == pytest.approx(60)
    s.handle(ev.action("rewind") | {"to_step": 50})
    s.handle(ev.channels({"k": 0.1}))
    s.advance(1)
    assert deg(s)["knee"] == pytest.approx(6)
