"""A live stream faster than the frame loop: the source's thread reads the socket's
whole backlog at once and retargets only the newest pose, and the queue to the frame
loop holds at most one frame, merged as a drain merges (skip-to-newest)."""

from __future__ import annotations

import socket
import time

from puppet.commands.streams import source_for
from puppet.data.catalog import load_setup
from puppet.input.live import LiveQueue
from puppet.interface import events as ev
from puppet.mocap import puppet_osc
from puppet.mocap.bvh import read_bvh
from puppet.mocap.send import encoder, load_bones
from puppet.mocap.source import OscSource


def test_channel_frames_merge_into_one_waiting_event():
    queue = LiveQueue()
    assert queue.post_merged(ev.channels({"a": 1.0, "b": 2.0}))
    assert queue.post_merged(ev.channels({"a": 3.0}))
    assert queue.pending() == 1 and queue.merged == 1
    assert queue.drain() == [ev.channels({"a": 3.0, "b": 2.0})]
    assert not queue.post_merged(ev.channels({"a": float("nan")}))  # still checked


def test_a_backlog_of_poses_retargets_only_the_newest():
    setup = load_setup("biped-mocap")
    walk = read_bvh("assets/mocap/cmu-131_01-walk.bvh")
    encode = encoder(walk, "vmc", load_bones("assets/mocap/cmu-bones.yaml"))
    many = source_for("udp://127.0.0.1:0", "vmc", None, setup)  # fed directly
    newest = source_for("udp://127.0.0.1:0", "vmc", None, setup)
    dgrams = [encode(k, k * walk.frame_time) for k in range(6)]
    assert many.receive_many(dgrams, arrival=5 / 120) == 1
    assert many.skipped == 5 and many.decoder.counts.frames == 6
    assert newest.receive(dgrams[-1], arrival=5 / 120) == 1
    assert many.queue.pending() == 1
    # what the backlog gives is the newest pose alone (its retargeting and filters saw
    # only it)
    assert many.drain(wall=0.05)[0]["values"] == newest.drain(wall=0.05)[0]["values"]


def test_the_listening_thread_keeps_one_frame_waiting():
    source = OscSource("puppet", port=0).start()
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
            for k in range(50):  # a burst, faster than any frame loop drains
                sock.sendto(puppet_osc.encode_frame(k / 120, {"a": float(k), f"c{k % 3}": 1.0}),
                            (source.host, source.port))
        deadline = time.monotonic() + 10.0
        while source.decoder.counts.frames < 50 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert source.decoder.counts.frames == 50
        assert source.queue.pending() == 1
        values = source.drain()[0]["values"]
        assert values == {"a": 49.0, "c0": 1.0, "c1": 1.0, "c2": 1.0}
    finally:
        source.close()
