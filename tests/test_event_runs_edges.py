"""The cat's pose grids and the several joints' rows in the kernel's event runs: mouse
moves no shipped log has (past both ends, infinite, NaN, ints, -0.0), the kernel's runs
against the pure-Python path. Passes: closes a coverage hole (test_event_runs_python's
clamps are on the rows' arithmetic alone)."""

from __future__ import annotations

import math

import pytest
from kernel_paths import needs_cc
from stepwise import stepwise
from test_event_runs import _counted, _log
from test_event_runs_python import _traced

from puppet.session.playback import play

ODD = [(-2.5, 3.0), (math.inf, -math.inf), (1e308, -1e308), (0, 1), (1, 0), (-0.0, -0.0),
       (0.9999999999999999, 1e-300)]
# (a grid clamps NaN to 0, as Python's ``x if x > 0.0 else 0.0``; a linear map's row
# writes NaN, which would make the rest of the rope swing's replay NaN: the cat's only)
NAN = [(0.5, math.nan), (math.nan, 0.25)]


def _odd(log, end: int, odd: list):
    """The log's events to ``end``, every 7th mouse move's values one of ODD's."""
    pairs, n = [], 0
    for at, event in log.pairs():
        if at > end:
            break
        if event["type"] == "mouse":
            n += 1
            if n % 7 == 0:
                x, y = odd[(n // 7) % len(odd)]
                event = {**event, "x": x, "y": y}
        pairs.append((at, event))
    log.pairs = lambda: pairs
    return log


@needs_cc
@pytest.mark.parametrize("name", ["cat-trot", "biped-rope-swing"])
def test_odd_mouse_values_in_the_kernels_runs(name, path_of):
    assert path_of("c") is not None
    end = 1500
    log, setup = _log(name)
    log = _odd(log, end, ODD + NAN if name == "cat-trot" else ODD)
    patcher, done = _counted()
    with patcher:
        got = _traced(play, log, setup, end, every=5)
    assert done[0] > 30, done  # the kernel's runs took most of the moves
    assert path_of("python") is None
    ref = _traced(stepwise, log, setup, end, every=5)
    assert len(got[0]) == len(ref[0]) > 100

    def same(a, b):  # (NaN targets: compared by their bits' repr)
        return repr(a) == repr(b)
    for a, b in zip(got[0], ref[0]):
        assert a[0] == b[0] and a[1] == b[1] and same(a[2], b[2]), a[0]
    assert same(got[1], ref[1])


# the gymnast's swing mode, with a one-joint map on the near shoulder before its two
# shoulders' map (which then writes over it) and one on the far shoulder after it (which
# then wins): Python's applier order, the kernel's rows' order
SHOULDERS = "    - {input: mouse.x, joints: {shoulder_near: 1, shoulder_far: 1}, from: [0.2, 0.8],"
HIPS = "    - {input: mouse.y, joints: {hip_near: 1, hip_far: 1}, from: [0.2, 0.8],"


@needs_cc
def test_two_maps_on_one_joint_in_the_kernels_runs(path_of):
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import setup_for_log

    assert path_of("c") is not None
    log = read_log("assets/logs/biped-rope-swing.jsonl")
    text = log.header["interface_text"]
    assert text.count(SHOULDERS) == 1 and text.count(HIPS) == 1
    text = text.replace(SHOULDERS, "    - {input: mouse.x, joint: shoulder_near, to: [0, 30]}\n"
                        + SHOULDERS)
    log.header["interface_text"] = text.replace(
        HIPS, "    - {input: mouse.x, joint: shoulder_far, to: [-40, 10]}\n" + HIPS)
    end = 3000
    got, ref = [], []
    patcher, done = _counted()
    with patcher:
        got = _traced(play, log, setup_for_log(log, as_recorded=True)[0], end, every=5)
    assert done[0] > 30, done
    assert path_of("python") is None
    ref = _traced(stepwise, log, setup_for_log(log, as_recorded=True)[0], end, every=5)
    assert len(got[0]) == len(ref[0]) > 100
    for a, b in zip(got[0], ref[0]):
        assert a[:3] == b[:3], a[0]
