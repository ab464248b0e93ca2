"""Candidate generators: a stage's input written by Python, where a spec cannot say it.

A spec's stage is normally a template (entries with arithmetic on its parameters).
Some performances are not a fixed template: a player that watches the swing and pumps
on its phase writes different entries for every run. Such a stage names a generator
(``generator: giant-swings``); its ``vary:`` parameters (and ``let:`` values) are the
generator's numbers, searched like any others.

The extension point: a function ``fn(run: GeneratorRun, values: dict) -> None``
registered in ``GENERATORS`` under a name. It plays the session from the stage's
checkpoint through ``run`` - ``run.add(entry)`` queues a script entry (absolute ``t``,
not before ``run.t``), ``run.advance(steps)`` steps the physics applying the queued
input at its exact steps - and may end the stage early with ``run.end_at(seconds)``.
The entries it added are the stage's input: the try replays them from the checkpoint
(so the score is the written log's), and the kept ones go into the script and log. A
generator reads the session (positions, contacts) but never changes it other than
through ``run``. Keep them small and deterministic (no clock, no global random state).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from puppet.timeline.script import ScriptSpec, compile_script

GENERATORS: dict[str, Callable] = {}


def register(name: str):
    def add(fn):
        GENERATORS[name] = fn
        return fn
    return add


class GeneratorRun:
    """A stage being played by a generator, from its checkpoint (see the module)."""

    def __init__(self, session, t0: float, end_step: int, fixed: list[dict],
                 mouse_from=(0.5, 0.5)):
        self.session = session
        self.dt = session.sim.dt
        self.t0 = t0
        self.end_step = end_step
        self.entries: list[dict] = []
        self._pending: list[tuple[int, int, dict]] = []  # (step, order, event)
        self._order = 0
        self._mouse = tuple(mouse_from)
        self.end: float | None = None
        for e in fixed:
            self.add(e)

    @property
    def t(self) -> float:
        return self.session.steps * self.dt

    @property
    def done(self) -> bool:
        return self.session.steps >= self.end_step or (
            self.end is not None and self.t >= self.end - 1e-9)

    def add(self, entry: dict) -> None:
        """Queue a script entry (``{t, mouse, over}``, ``{t, key, hold}``...)."""
        entry = dict(entry)
        if entry["t"] < self.t - self.dt / 2:  # (rounded to 0.1 ms: the same step)
            raise ValueError(f"a generator's entry at t = {entry['t']:g} s is in the past "
                             f"(now {self.t:g} s)")
        spec = ScriptSpec.model_validate({"events": [{"t": 0.0, "mouse": list(self._mouse)},
                                                     entry]})
        for step, event in compile_script(spec, self.dt)[1:]:
            self._pending.append((step, self._order, event))
            self._order += 1
        self._pending.sort(key=lambda p: (p[0], p[1]))
        if "mouse" in entry:
            self._mouse = tuple(entry["mouse"])
        self.entries.append(entry)

    def advance(self, steps: int) -> None:
        """Step the physics ``steps`` steps, each queued event at its own step."""
        target = min(self.session.steps + steps, self.end_step)
        s = self.session
        while s.steps < target:
            while self._pending and self._pending[0][0] <= s.steps:
                s.handle(self._pending.pop(0)[2])
            nxt = self._pending[0][0] if self._pending else target
            s.advance(max(1, min(nxt, target) - s.steps))

    def end_at(self, seconds: float) -> None:
        """End the stage at ``seconds`` (absolute), before its written length."""
        self.end = round(seconds, 4)


def generate(name: str, session, values: dict, t0: float, end_step: int,
             fixed: list[dict] | None = None,
             mouse_from=(0.5, 0.5)) -> tuple[list[dict], float | None]:
    """(the entries generator ``name`` wrote from this checkpoint, where it ended the
    stage or None)."""
    run = GeneratorRun(session, t0, end_step, fixed or [], mouse_from)
    GENERATORS[name](run, values)
    return run.entries, run.end


# -- the shipped generators ----------------------------------------------------------
@register("giant-swings")
def giant_swings(run: GeneratorRun, p: dict) -> None:
    """The gymnast pumping a swing on the high bar (biped-gymnast, swing mode): every
    1/60 s it reads the centre of mass's angle about the held bar and its turning rate,
    and sweeps the mouse to the pike point (``pike_x``, ``pike_y``: arms close, hips
    piked, the body shortened) while the swing rises between ``lo`` and ``hi`` degrees
    from hanging, to the arch point (``arch_x``, ``arch_y``: stretched) otherwise, each
    change a glide of ``glide`` s after a reaction ``delay``. From ``start`` s; after
    ``turns`` full turns it stops pumping and the stage ends ``settle`` s later."""
    session = run.session
    tick = 8
    bar = session.sim.grasp_point("hand_near") or (0.0, 2.8)

    def angle() -> float:
        x, y = session.character.com()
        return math.atan2(x - bar[0], -(y - bar[1]))  # 0 hanging below, + forward

    r = lambda v: round(v, 4)  # noqa: E731
    arch, pike = (p["arch_x"], p["arch_y"]), (p["pike_x"], p["pike_y"])
    run.add({"t": r(run.t), "mouse": [r(arch[0]), r(arch[1])]})
    free = run.t0 + p.get("start", 0.5)
    prev = angle()
    unwrapped = top = 0.0
    choice = want = "arch"
    since = session.steps
    stopped_at = None
    while not run.done:
        run.advance(tick)
        a = angle()
        d = math.remainder(a - prev, 2 * math.pi)
        prev = a
        unwrapped += d
        w = d / (tick * run.dt)
        top = max(top, abs(unwrapped))
        t = run.t
        if stopped_at is None and top >= p.get("turns", 4.0) * 2 * math.pi:
            stopped_at = t
            run.end_at(t + p.get("settle", 3.0))
        if t < free:
            continue
        phase = math.degrees(math.remainder(a, 2 * math.pi))
        up = phase * w > 0 and p["lo"] <= abs(phase) <= p["hi"] and stopped_at is None
        new = "pike" if up else "arch"
        if new != want:
            want, since = new, session.steps
        if want != choice and (session.steps - since) * run.dt >= p["delay"] - 1e-9:
            choice = want
            target = pike if up else arch
            run.add({"t": r(t), "mouse": [r(target[0]), r(target[1])], "over": r(p["glide"])})


NONE = "none"  # a key choice that presses nothing


@register("key-turn")
def key_turn(run: GeneratorRun, p: dict) -> None:
    """One turn of a key-driven climb (biped-ladder's g and t): the turn's key ``key``
    ``lead`` s after the checkpoint, with an optional posture key ``pre`` (a key, or
    ``none``) ``pre_gap`` s before it and an optional ``post`` ``post_gap`` s after it;
    the stage ends ``phase`` (+ ``settle``) s after the turn's key, so its length
    depends on whether ``pre`` is pressed - what a template cannot say. A gap of an
    absent key changes nothing (the same try under another name)."""
    at = run.t0 + p.get("lead", 0.01)
    pre, post = p.get("pre", NONE), p.get("post", NONE)
    if pre != NONE:
        run.add({"t": round(at, 4), "key": str(pre)})
        at += p["pre_gap"]
    run.add({"t": round(at, 4), "key": str(p["key"])})
    if post != NONE:
        run.add({"t": round(at + p["post_gap"], 4), "key": str(post)})
    run.end_at(round(at + p["phase"], 4) + p.get("settle", 0.0))


GRIP_KEYS = {"hand_near": "z", "hand_far": "x", "foot_near": "a", "foot_far": "s"}


@register("grip-stroke")
def grip_stroke(run: GeneratorRun, p: dict) -> None:
    """One regrasp phase of the gymnast's rigid grips (biped-gymnast: z, x, a, s grip
    and let go of a hand or foot): the limbs whose ``let:`` flag is 1 (``hand_near``,
    ``hand_far``, ``foot_near``, ``foot_far``) move. Optionally (``preload`` 1) the mouse
    first goes to (``x``, ``pre_y``) in ``preload_s`` s while every limb still holds;
    then the moving limbs that hold let go (a foot on the floor holds nothing: it is
    only armed), the mouse strokes to (``x``, ``y``) in ``duration`` s, and each moving
    limb's key comes again ``rearm_hand`` / ``rearm_foot`` s after the let-go (armed: it
    catches the first rung within reach). The stage ends ``settle`` (+ ``tail``) s after
    the stroke. Which keys let go depends on what holds at the checkpoint, and the
    preload on a choice moves every time after it: what a template cannot say."""
    sim = run.session.sim
    limbs = [n for n in GRIP_KEYS if p.get(n)]  # hands first, near before far
    t0 = run.t0
    x, duration = p["x"], p["duration"]
    loaded = bool(p.get("preload", 0))
    lead = p.get("preload_s", 0.4) + 0.05
    if loaded:
        run.add({"t": round(t0 + 0.01, 4), "mouse": [x, p["pre_y"]],
                 "over": p.get("preload_s", 0.4)})
        t0 += lead
    for limb in limbs:
        if limb in sim.grasps:
            run.add({"t": round(t0 + 0.01, 4), "key": GRIP_KEYS[limb]})  # let go
    run.add({"t": round(t0 + 0.01, 4), "mouse": [x, p["y"]], "over": duration})
    rearm = {n: p["rearm_hand"] if n.startswith("hand") else p["rearm_foot"] for n in limbs}
    for limb in sorted(limbs, key=lambda n: rearm[n]):
        run.add({"t": round(t0 + 0.01 + rearm[limb], 4), "key": GRIP_KEYS[limb]})  # armed
    end = run.t0 + 0.01 + duration + p.get("settle", 0.8) + (lead if loaded else 0.0)
    run.end_at(round(end, 4) + p.get("tail", 0.0))
