"""Fuzzing the OSC packet decoders (VMC, MediaPipe pose, puppet's channels address):
random bytes, mutated real frames, valid-shaped messages with garbage values, wrong
argument counts and types, bundles of them. Every case is fed to all three decoders:
never an exception, every message accepted, ignored or dropped (and each drop counted
by its reason), every frame handed out finite and in range. A case counts as
"accepted" by a decoder when it used some of it (a message or a frame), else "refused".

The default run is bounded (a seeded loop of ``PUPPET_OSC_FUZZ`` mutated datagrams,
10,000 by default, about 2 s, and ``PUPPET_FUZZ_CASES`` hypothesis cases per
strategy); the long run is ``pytest -m fuzz`` (``PUPPET_FUZZ_LONG`` per strategy,
7,000 by default, and ten times the loop). The counts go into the fuzz summary.
"""

from __future__ import annotations

import math
import os
import random
import struct

import fuzzing
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
from pythonosc.osc_message_builder import OscMessageBuilder

from puppet.mocap import mediapipe, mediapipe_bridge, puppet_osc, vmc
from puppet.mocap.bvh import read_bvh
from puppet.mocap.formats import DECODERS
from puppet.mocap.osc import MAX_POSITION
from puppet.mocap.send import encoder, load_bones

SHORT = int(os.environ.get("PUPPET_FUZZ_CASES", "150"))
LONG = int(os.environ.get("PUPPET_FUZZ_LONG", "7000"))
LOOP = int(os.environ.get("PUPPET_OSC_FUZZ", "10000"))
KIND = {"vmc": "osc-vmc", "mediapipe": "osc-mp", "mediapipe-osc": "osc-mp-bridge",
        "puppet": "osc-puppet"}
FRAME_LEVEL = ("out_of_order", "stale")  # drops of a whole frame, not of a message

_clip = read_bvh("assets/mocap/cmu-131_01-walk.bvh")
_table = load_bones("assets/mocap/cmu-bones.yaml")
_vmc, _mp = encoder(_clip, "vmc", _table), encoder(_clip, "mediapipe", _table)
_bridge = encoder(_clip, "mediapipe-osc", _table)
SEEDS = [_vmc(0, 0.0), _vmc(500, 4.1), _mp(0, 0.0), _mp(700, 5.8), _bridge(300, 0.0),
         mediapipe_bridge.encode_pose(None), mediapipe_bridge.encode_pose(
             {"left_hip": (0.5, 0.5, 0.0)}, count=False),
         puppet_osc.encode_frame(1.0, {"lean": 0.5, "arm.x": -0.25}),
         puppet_osc.encode_frame(None, {f"c{i}": i / 10 for i in range(20)})]


def _settings(n):
    return settings(max_examples=n, derandomize=True, database=None, deadline=None,
                    suppress_health_check=list(HealthCheck), print_blob=True)


def check(dgram: bytes, decoders: dict) -> None:
    """Feed ``dgram`` to each decoder; the invariants hold, or the test fails."""
    for name, d in decoders.items():
        c = d.counts
        before = (c.packets, c.messages, c.accepted, c.ignored, dict(c.dropped), c.frames,
                  c.skipped)
        frames = d.feed(dgram)  # an exception fails the test
        dropped = {r: n for r in c.dropped if (n := c.dropped[r] - before[4].get(r, 0))}
        message_drops = sum(n for r, n in dropped.items() if r not in FRAME_LEVEL)
        assert c.packets == before[0] + 1
        new_messages = c.messages - before[1]
        skipped = c.skipped - before[6]  # bundle elements python-osc could not read
        if new_messages == 0:  # did not parse (one malformed drop), or an empty bundle
            assert sum(dropped.values()) - skipped in (0, 1) and frames == []
            assert set(dropped) <= {"malformed"}
        else:
            assert new_messages + skipped == (c.accepted - before[2]) \
                + (c.ignored - before[3]) + message_drops
        assert c.frames - before[5] == len(frames)
        for frame in frames:
            for p in frame.points.values():
                assert len(p) == 3 and all(math.isfinite(v) and abs(v) <= 1e4 for v in p)
            for v in frame.channels.values():
                assert math.isfinite(v) and abs(v) <= 1e6
            if frame.time is not None:
                assert math.isfinite(frame.time)
        took = c.accepted > before[2] or frames  # some of it was used
        outcome = "accepted" if took else "refused"
        fuzzing.STATS[(KIND[name], outcome)] += 1


def fresh() -> dict:
    return {name: cls() for name, cls in DECODERS.items()}


def mutate(data: bytes, rng: random.Random) -> bytes:
    b = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        op = rng.randrange(6)
        i = rng.randrange(len(b)) if b else 0
        if op == 0 and b:
            b[i] = rng.randrange(256)
        elif op == 1:
            del b[i:i + rng.randint(1, 16)]
        elif op == 2:
            b[i:i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 16)))
        elif op == 3 and len(b) >= 4:  # a size or a number: a 4-byte word
            j = i - i % 4
            b[j:j + 4] = struct.pack(">i", rng.choice([0, -1, 1, 2 ** 31 - 1, -2 ** 31,
                                                       rng.randrange(-9999, 9999)]))
        elif op == 4 and len(b) >= 4:  # a float: NaN, inf, huge, tiny
            j = i - i % 4
            b[j:j + 4] = struct.pack(">f", rng.choice([math.nan, math.inf, -math.inf, 3e38,
                                                       1e-45, -0.0, 1e5]))
        else:
            b = b[:i]
    return bytes(b)


def _loop(n: int, seed: int) -> None:
    rng = random.Random(seed)
    decoders = fresh()
    for k in range(n):
        if k % 500 == 0:
            decoders = fresh()  # clocks start again now and then
        r = rng.random()
        if r < 0.15:
            dgram = bytes(rng.randrange(256) for _ in range(rng.randint(0, 200)))
        elif r < 0.25:
            dgram = rng.choice([b"#bundle\x00", b"/", b"/VMC/Ext/OK\x00", b""]) + bytes(
                rng.randrange(256) for _ in range(rng.randint(0, 64)))
        else:
            dgram = mutate(rng.choice(SEEDS), rng)
        check(dgram, decoders)


def test_ten_thousand_mutated_datagrams_never_raise_and_every_drop_is_counted():
    _loop(LOOP, 11)


@pytest.mark.fuzz
def test_long_loop_of_mutated_datagrams():
    _loop(10 * LOOP, 12)


# -- hypothesis: valid-shaped messages with garbage, wrong counts and types ------------
ADDRESSES = st.sampled_from([vmc.BONE, vmc.ROOT, vmc.TIME, vmc.OK, "/VMC/Ext/Blend/Val",
                             mediapipe.ADDRESS, puppet_osc.ADDRESS, "/x", "/VMC/Ext/Bone",
                             "/puppet/channels/extra"])
GARBAGE = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=32).map(lambda v: ("f", v)),
    st.floats(allow_nan=True, allow_infinity=True).map(lambda v: ("d", v)),
    st.integers(-2 ** 31, 2 ** 31 - 1).map(lambda v: ("i", v)),
    st.integers(-2 ** 63, 2 ** 63 - 1).map(lambda v: ("h", v)),
    st.sampled_from(["Hips", "LeftFoot", "Tail", "", "left_hip", "lean", "mocap.fresh",
                     "9x", "x" * 300]).map(lambda v: ("s", v)),
    st.text(max_size=12).filter(lambda s: "\x00" not in s).map(lambda v: ("s", v)),
    st.binary(min_size=1, max_size=12).map(lambda v: ("b", v)),
    st.booleans().map(lambda v: ("T" if v else "F", v)),
    st.just(("N", None)),
)
COUNTS = st.sampled_from([0, 1, 2, 3, 7, 8, 9, 13, 14, 15, 131, 132, 133, 134])


def _message(address: str, args) -> object:
    b = OscMessageBuilder(address=address)
    for kind, value in args:
        b.add_arg(value, kind)
    return b.build()


@st.composite
def garbage_message(draw):
    address = draw(ADDRESSES)
    n = draw(COUNTS)
    if n > 20:  # long argument lists: mostly floats, a few garbage
        args = [("f", draw(st.floats(-2, 2, width=32)))] * n
        for _ in range(draw(st.integers(0, 3))):
            args[draw(st.integers(0, n - 1))] = draw(GARBAGE)
    else:
        args = draw(st.lists(GARBAGE, min_size=n, max_size=n))
    return _message(address, args)


@st.composite
def shaped_message(draw):
    """Right address and count, a right type in most places, garbage in a few."""
    kind = draw(st.sampled_from(["bone", "root", "pose", "channels"]))
    if kind in ("bone", "root"):
        name = draw(st.sampled_from(["Hips", "Spine", "LeftFoot", "Tail", "root"]))
        args = [("s", name)] + [("f", draw(st.floats(-1, 1, width=32))) for _ in range(7)]
        address = vmc.BONE if kind == "bone" else vmc.ROOT
    elif kind == "pose":
        args = [("f", draw(st.floats(-1, 1, width=32))) for _ in range(132)]
        address = mediapipe.ADDRESS
    else:
        args = []
        for i in range(draw(st.integers(1, 6))):
            args += [("s", f"c{i}"), ("f", draw(st.floats(-5, 5, width=32)))]
        address = puppet_osc.ADDRESS
    for _ in range(draw(st.integers(0, 3))):
        args[draw(st.integers(0, len(args) - 1))] = draw(GARBAGE)
    return _message(address, args)


def _bundle(messages) -> bytes:
    b = OscBundleBuilder(IMMEDIATELY)
    for m in messages:
        b.add_content(m)
    return b.build().dgram


MESSAGES = st.one_of(garbage_message(), shaped_message())
DATAGRAMS = st.one_of(MESSAGES.map(lambda m: m.dgram),
                      st.lists(MESSAGES, min_size=1, max_size=6).map(_bundle),
                      st.binary(max_size=300))


def _given(n):
    return lambda f: _settings(n)(given(st.lists(DATAGRAMS, min_size=1, max_size=4))(f))


def _stream(datagrams):
    decoders = fresh()
    for dgram in datagrams:
        check(dgram, decoders)


@_given(SHORT)
def test_garbage_shaped_messages_and_bundles_never_raise(datagrams):
    _stream(datagrams)


@pytest.mark.fuzz
@_given(LONG)
def test_long_garbage_shaped_messages_and_bundles(datagrams):
    _stream(datagrams)


def test_the_fuzz_seeds_decode():
    decoders = fresh()
    made = {name: sum(len(d.feed(s)) for s in SEEDS) for name, d in decoders.items()}
    # (the bridge's older form, no count, is 132 numbers as mediapipe's own: both read it)
    assert made == {"vmc": 2, "mediapipe": 3, "mediapipe-osc": 2, "puppet": 2}
    assert MAX_POSITION == 100.0
