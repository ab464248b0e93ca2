"""A log's input as a person would play it again: every event moved by a human's error.

``perturb`` takes a log's ``(step, event)`` pairs and returns a new list, the same
events moved in time (and the mouse and sticks in space) by the errors of a
``puppet.data.playtest.Noise``:

- timing: each event moves by an error drawn uniformly from +-``timing_ms`` of *real*
  time, divided by the slowdown in force at it and rounded to steps (slowed down 3x,
  +-30 ms is +-10 ms of simulated time: about +-5 steps at 1/480 s);
- a mouse or stick *stroke* (its samples with no pause of ``stroke_gap_ms`` between
  them) moves as a whole: one time shift, one tempo (its length scaled by
  1 +- ``tempo``), one aim offset (+-``aim_px`` per axis, of a 1024 x 640 window; a
  stick's +-``stick_aim``), plus each sample's own tremor (+-``tremor_px``);
  a drag moves in time as a stroke does; a stream of mocap frames or a plugin channel
  only by its time shift (a performer's take, not a hand's stroke);
- one input's events keep their order (a key, a button, the mouse...), and events at
  distinct steps stay at distinct steps: a key is never released before it is pressed;
- checkpoint markers (the action, the app's checkpoint key), hot reloads and gesture
  bindings move with the event after them; so do the events that send time back
  (restore, rewind, take, the scrub keys), which also cut the log into segments each
  moved on its own;
- nothing moves before step 0 or past the log's end.

The draws depend only on (seed, try, segment, input): the same seed gives the same
tries in any process, and a log's mouse does not change the draws of its keys.
"""

from __future__ import annotations

import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from puppet.data.keys import GAMEPAD_STICKS, GAMEPAD_TRIGGERS, normalize_key
from puppet.data.playtest import REFERENCE_WINDOW, Noise
from puppet.interface.events import Event

# what an event is to the player (``classify``)
PRESS = "press"  # a key or button: each event its own error, order kept per input
STROKE = "stroke"  # samples of a position: moved as strokes
SINGLE = "single"  # one event of its own (a push, a reset)
MARKER = "marker"  # moves with the event after it
TRAVEL = "travel"  # time goes back: a marker that also begins a new segment

_TRAVEL_ACTIONS = ("restore", "rewind", "take")
STREAMS = ("channels",)  # inputs a stroke of which is not a hand's (no tempo)


@dataclass
class Move:
    """How one event moved: its index in the log, the steps, and the real-time error
    drawn for it (its stroke's shift for a stroke's sample, 0 for a marker)."""

    index: int
    step: int
    new_step: int
    real_shift: float  # s of real time (before the slowdown and the rounding)


@dataclass
class Perturbation:
    pairs: list[tuple[int, Event]]  # the moved log, in the order it plays
    moves: list[Move] = field(default_factory=list)  # per original event, in log order


def classify(event: Event, app_keys: dict[str, str]) -> tuple[str, str]:
    """(what it is to the player, the input it belongs to)."""
    kind = event["type"]
    if kind == "mouse":
        return STROKE, "mouse"
    if kind == "key":
        chord = normalize_key(event["key"])
        if chord == app_keys.get("checkpoint"):
            return MARKER, "key:" + chord
        if chord in (app_keys.get("restore"), app_keys.get("rewind"), app_keys.get("forward")):
            return TRAVEL, "key:" + chord
        return PRESS, "key:" + chord
    if kind == "mouse_button":
        return PRESS, "button:" + event["button"]
    if kind == "gamepad":
        name = event["name"]
        if name in GAMEPAD_STICKS:
            return STROKE, "stick:" + name.rsplit("_", 1)[0]  # x and y: one stroke
        if name in GAMEPAD_TRIGGERS or name.startswith("axis"):
            return STROKE, "stick:" + name
        return PRESS, "gamepad:" + name
    if kind == "channel":
        return STROKE, "channel:" + event["name"]
    if kind == "channels":
        return STROKE, "channels"
    if kind == "drag":
        return STROKE, "drag"
    if kind == "push":
        return SINGLE, "push"
    if kind == "action":
        name = event["name"]
        if name == "checkpoint":
            return MARKER, "action"
        if name in _TRAVEL_ACTIONS:
            return TRAVEL, "action"
        return SINGLE, "action:" + name
    return MARKER, kind  # reload, gesture: the player's file edits, not their hands


def _rng(seed: int, try_index: int, segment: int, name: str) -> np.random.Generator:
    return np.random.default_rng([seed, try_index, segment, zlib.crc32(name.encode())])


def _uniform(rng: np.random.Generator, bound: float, n: int | None = None):
    """Uniform draws in -bound..bound (drawn even when bound is 0, so one parameter
    set to 0 leaves the other draws as they were)."""
    return rng.uniform(-1.0, 1.0, n) * bound


def _strokes(indices: list[int], pairs, slowdowns, dt: float, gap_ms: float,
             kind: str) -> list[list[int]]:
    """An input's events cut into strokes at pauses of at least ``gap_ms`` real ms
    (a drag: each from its start to its end)."""
    strokes: list[list[int]] = []
    for i in indices:
        if strokes:
            last = strokes[-1][-1]
            pause = (pairs[i][0] - pairs[last][0]) * dt * slowdowns[i] * 1000.0
            new = pairs[i][1].get("phase") == "start" if kind == "drag" else pause >= gap_ms
            if not new:
                strokes[-1].append(i)
                continue
        strokes.append([i])
    return strokes


def _clamp(value: float, lo: float, hi: float) -> float:
    return lo if value < lo else hi if value > hi else value


def _offset_sample(event: Event, name: str, dxy, tremor) -> Event:
    """A mouse or stick sample moved by its stroke's offset and its own tremor."""
    if event["type"] == "mouse":
        return dict(event, x=_clamp(event["x"] + dxy[0] + tremor[0], 0.0, 1.0),
                    y=_clamp(event["y"] + dxy[1] + tremor[1], 0.0, 1.0))
    if event["type"] == "gamepad":
        axis = 1 if event["name"].endswith("_y") else 0
        lo = 0.0 if event["name"] in GAMEPAD_TRIGGERS else -1.0
        return dict(event, value=_clamp(event["value"] + dxy[axis] + tremor[axis], lo, 1.0))
    return event


def perturb(pairs: Sequence[tuple[int, Event]], slowdowns: Sequence[float], dt: float,
            end_step: int, noise: Noise, seed: int, try_index: int,
            app_keys: dict[str, str]) -> Perturbation:
    """The log's events moved as one try of a person's replay (see the module's
    docstring). ``slowdowns``: the slowdown in force at each event (``slowdown``'s
    ``in_force``); ``app_keys``: the interface's app action -> key (its checkpoint and
    restore keys are markers)."""
    n = len(pairs)
    kinds = [classify(e, app_keys) for _, e in pairs]
    # segments: cut before each event that sends time back
    segments: list[list[int]] = [[]]
    for i, (what, _) in enumerate(kinds):
        if what == TRAVEL and segments[-1]:
            segments.append([])
        segments[-1].append(i)
    new_step = [0] * n
    real = [0.0] * n
    values: dict[int, Event] = {}
    mouse_scale = (noise.aim_px / REFERENCE_WINDOW[0], noise.aim_px / REFERENCE_WINDOW[1])
    tremor_scale = (noise.tremor_px / REFERENCE_WINDOW[0],
                    noise.tremor_px / REFERENCE_WINDOW[1])
    timing = noise.timing_ms / 1000.0
    anchor: dict[int, int] = {}  # a marker -> the event it moves with
    for seg_index, segment in enumerate(segments):
        inputs: dict[str, list[int]] = {}
        for i in segment:
            what, name = kinds[i]
            if what not in (MARKER, TRAVEL):
                inputs.setdefault(name, []).append(i)
        for name, indices in inputs.items():
            rng = _rng(seed, try_index, seg_index, name)
            what = kinds[indices[0]][0]
            if what != STROKE:
                shifts = _uniform(rng, timing, len(indices))
                for i, s in zip(indices, shifts):
                    real[i] = float(s)
                    new_step[i] = pairs[i][0] + round(s / slowdowns[i] / dt)
            else:
                spatial = name == "mouse" or name.startswith("stick:")
                aim = mouse_scale if name == "mouse" else (noise.stick_aim, noise.stick_aim)
                shake = tremor_scale if name == "mouse" else (noise.stick_tremor,
                                                              noise.stick_tremor)
                for stroke in _strokes(indices, pairs, slowdowns, dt, noise.stroke_gap_ms,
                                       name):
                    shift, tempo, ax, ay = (float(v) for v in _uniform(rng, 1.0, 4))
                    s0 = pairs[stroke[0]][0]
                    # a hand's stroke is played faster or slower; a stream (mocap frames,
                    # a plugin's channel) is someone's whole take: only moved in time
                    scale = 1.0 + tempo * noise.tempo if name not in STREAMS \
                        and not name.startswith("channel:") else 1.0
                    for i in stroke:
                        step_shift = shift * timing / slowdowns[i] / dt
                        real[i] = shift * timing
                        new_step[i] = round(s0 + (pairs[i][0] - s0) * scale + step_shift)
                    if spatial:
                        offset = (ax * aim[0], ay * aim[1])
                        tremors = _uniform(rng, 1.0, (len(stroke), 2))
                        for i, (tx, ty) in zip(stroke, tremors):
                            values[i] = _offset_sample(pairs[i][1], name, offset,
                                                       (tx * shake[0], ty * shake[1]))
            # one input's events in their order; distinct steps stay distinct
            for a, b in zip(indices, indices[1:]):
                least = new_step[a] + min(1, pairs[b][0] - pairs[a][0])
                if new_step[b] < least:
                    new_step[b] = least
        # markers (and the travel event that opens the segment) go with the next event
        following = None
        for i in reversed(segment):
            if kinds[i][0] in (MARKER, TRAVEL):
                if following is not None:
                    new_step[i] = pairs[i][0] + new_step[following] - pairs[following][0]
                    real[i] = real[following]
                    anchor[i] = following
                else:
                    new_step[i] = pairs[i][0]
            else:
                following = i
    for i in range(n):
        new_step[i] = min(max(new_step[i], 0), end_step)
    order: list[int] = []
    for segment in segments:
        # the event that sent time back first (the steps after it are on the new time
        # line); then by new step, a marker just before the event it goes with, ties in
        # log order
        head = segment[:1] if segment and kinds[segment[0]][0] == TRAVEL else []
        order.extend(head)
        order.extend(sorted(segment[len(head):],
                            key=lambda i: (new_step[i], anchor.get(i, i),
                                           0 if i not in anchor else -1, i)))
    moved = [(new_step[i], values.get(i, pairs[i][1])) for i in order]
    moves = [Move(i, pairs[i][0], new_step[i], real[i]) for i in range(n)]
    return Perturbation(moved, moves)
