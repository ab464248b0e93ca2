"""One try of a stage, wherever it runs: back to the stage's checkpoint, the candidate's
input, the run sampled as ``puppet replay`` samples it, the score.

A ``Context`` is what every try of one stage shares: how to make the session, the
input up to and including the stage's checkpoint, the terms. A worker plays that input
once and keeps the session (``_PREPARED``, per process); every try then goes back to
the checkpoint (the ``restore`` action, as a person at the window would) and plays its
own input. The checkpoint re-seats the run (``Session.checkpoint``), so a try gives the
bits the written log gives when replayed straight through: what the search saw is
what the log shows. ``run_try`` depends only on its task, so any process, local or on
a cluster, returns the same result for it.
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict
from dataclasses import dataclass, field

from puppet.data.catalog import Setup
from puppet.interface import events as ev
from puppet.session.playback import play
from puppet.timeline.other_physics import OtherPhysics, rescaled_pairs
from puppet.timeline.trajectory import Sampler, sample_every
from puppet.timeline.tuning.scoring import BLOWUP_PENALTY, Judged, Term, judge, stretch

Pairs = list[tuple[int, dict]]
KEEP_SESSIONS = 2  # prepared stages a worker keeps (the current one and its neighbour)
MAX_VERSIONS = 60  # reloaded interfaces a kept session may pile up before it is rebuilt


@dataclass
class Context:
    """What the tries of one stage share. ``setup_from``: ('names', interface, scene,
    folder) or ('log', path); ``prefix``: the input up to and including the stage's
    checkpoint at ``stage_step``."""

    key: str
    setup_from: tuple
    dt: float
    interval: float
    prefix: Pairs
    stage_step: int
    t0: float
    terms: list[Term]
    until: list = field(default_factory=list)
    touches: bool = False
    playtest: tuple | None = None  # (Noise, tries, weight, (OtherPhysics, ...))
    seed: int = 0
    generator: str | None = None
    mouse_from: tuple[float, float] = (0.5, 0.5)
    physics: OtherPhysics | None = None  # a playtest variant's settings (None: the spec's)


@dataclass
class Task:
    context: Context
    pairs: Pairs  # the candidate's input after the checkpoint, up to ``end_step``
    end_step: int
    look_step: int
    look_pairs: Pairs = field(default_factory=list)  # more input in the look-ahead
    params: dict = field(default_factory=dict)  # (a generator reads them)
    fixed: list[dict] = field(default_factory=list)  # the template's entries (a generator's)


@dataclass
class TryResult:
    score: float
    accepted: bool  # every required term held, no blow-up
    until_ok: bool  # the stage's 'until' held at its end (True when it has none)
    judged: list[Judged]
    blowups: int = 0
    pass_rate: float | None = None
    entries: list[dict] | None = None  # what a generator wrote
    end: float | None = None  # where a generator ended the stage (s), if before its length

    def to_dict(self) -> dict:
        return {"score": self.score, "accepted": self.accepted, "until_ok": self.until_ok,
                "judged": [j.to_list() for j in self.judged], "blowups": self.blowups,
                "pass_rate": self.pass_rate, "entries": self.entries, "end": self.end}

    @classmethod
    def from_dict(cls, d: dict) -> TryResult:
        return cls(d["score"], d["accepted"], d["until_ok"],
                   [Judged.from_list(r) for r in d["judged"]], d["blowups"], d["pass_rate"],
                   d["entries"], d["end"])


class _Prepared:
    def __init__(self, ctx: Context):
        from puppet.session import Session

        setup = _setup(ctx.setup_from)
        if ctx.physics is not None:
            setup = ctx.physics.adjust(setup)
        self.session = Session(setup, dt=ctx.dt, checkpoint_interval=ctx.interval)
        self.sampler = Sampler(self.session, touches=ctx.touches)
        self.sampler(self.session)
        play(self.session, ctx.prefix, ctx.stage_step, sample_every(self.session.sim.dt),
             self.sampler)
        if self.session.steps != ctx.stage_step:
            raise RuntimeError(f"the start ran to step {self.session.steps}, not to the "
                               f"stage's checkpoint at {ctx.stage_step}")
        self.rows = list(self.sampler.rows)

    def back(self) -> None:
        """To the stage's checkpoint, its samples as they were there."""
        self.session.handle(ev.action("restore"))
        self.sampler.rows = list(self.rows)


_PREPARED: OrderedDict[str, _Prepared] = OrderedDict()
_SETUPS: dict[tuple, Setup] = {}


def _setup(source: tuple) -> Setup:
    if source not in _SETUPS:
        if source[0] == "log":
            from puppet.timeline.log import read_log
            from puppet.timeline.replay import setup_for_log

            _SETUPS[source] = setup_for_log(read_log(source[1]))[0]
        else:
            from puppet.data.catalog import load_setup

            _, interface, scene, folder = source
            _SETUPS[source] = load_setup(interface, scene, (folder,) if folder else None)
    return _SETUPS[source]


def prepared(ctx: Context, keep: int = KEEP_SESSIONS) -> _Prepared:
    """The stage's session at its checkpoint (this process keeps the last ``keep``)."""
    prep = _PREPARED.get(ctx.key)
    if prep is not None and len(prep.session.versions) > MAX_VERSIONS:
        prep = None  # every try's reloaded interface kept: start again, lighter
    if prep is None:
        prep = _Prepared(ctx)
        _PREPARED[ctx.key] = prep
        while len(_PREPARED) > keep:
            _PREPARED.popitem(last=False)
    _PREPARED.move_to_end(ctx.key)
    return prep


def _play(prep: _Prepared, pairs: Pairs, until: int):
    """Back to the checkpoint, ``pairs`` played to step ``until``; the trajectory and
    the blow-ups on the way."""
    prep.back()
    session, sampler = prep.session, prep.sampler
    before = session.blowups
    play(session, pairs, until, sample_every(session.sim.dt), sampler)
    if not sampler.rows or sampler.rows[-1][0] != session.steps:
        sampler(session)
    return sampler.trajectory(), session.blowups - before


def upto(traj, step: int):
    """The samples at or before ``step``."""
    import dataclasses

    import numpy as np

    keep = traj.step <= step
    out = {}
    for f in dataclasses.fields(traj):
        value = getattr(traj, f.name)
        if isinstance(value, np.ndarray) and value.shape[:1] == traj.t.shape:
            value = value[keep]
        out[f.name] = value
    return type(traj)(**out)


def run_try(task: Task) -> TryResult:
    """Play one candidate from its stage's checkpoint and score it."""
    ctx = task.context
    prep = prepared(ctx)
    pairs, entries, end = task.pairs, None, None
    end_step, look_step = task.end_step, task.look_step
    if ctx.generator is not None:
        from puppet.timeline.tuning.generators import generate

        prep.back()
        entries, end = generate(ctx.generator, prep.session, task.params, ctx.t0,
                                task.end_step, task.fixed, ctx.mouse_from)
        if end is not None:
            end_step = min(end_step, round(end / ctx.dt))
            look_step = end_step + task.look_step - task.end_step
        pairs = stage_pairs(entries, ctx.dt, ctx.mouse_from, end_step)
    traj, blowups = _play(prep, pairs + task.look_pairs, look_step)
    score, ok, judged = judge(ctx.terms, stretch(traj, ctx.t0), traj)
    until_ok = True
    if ctx.until:
        from puppet.timeline.expectations import evaluate

        at_end = upto(traj, end_step)
        until_ok = all(evaluate(e, at_end, "").passed for e in ctx.until)
    if blowups:
        score -= BLOWUP_PENALTY * blowups
        ok = False
    result = TryResult(score, ok, until_ok, judged, blowups, None, entries, end)
    if ok and ctx.playtest is not None:
        noise, tries, weight, variants = ctx.playtest
        keep = KEEP_SESSIONS * (1 + len(variants))
        passes = sum(_noisy_passes(prep, ctx, pairs, end_step, look_step, task.look_pairs,
                                   noise, i) for i in range(tries))
        for physics in variants:  # the same tries on cheaper physics: not a knife edge
            vctx, ratio = variant(ctx, physics)
            vprep = prepared(vctx, keep)
            vpairs, vlook = rescaled_pairs(pairs, ratio), rescaled_pairs(task.look_pairs, ratio)
            passes += sum(_noisy_passes(vprep, vctx, vpairs, round(end_step * ratio),
                                        round(look_step * ratio), vlook, noise, i)
                          for i in range(tries))
        prepared(ctx, keep)  # (the stage's own session stays the most recent)
        result.pass_rate = passes / (tries * (1 + len(variants)))
        result.score += weight * result.pass_rate
    return result


def variant(ctx: Context, physics: OtherPhysics) -> tuple[Context, float]:
    """The stage on other physics: its input up to the checkpoint at the steps nearest
    their times, the same checkpoint; and the ratio of the steps (old step / new)."""
    ratio = 1.0 if physics.dt is None else ctx.dt / physics.dt
    return dataclasses.replace(
        ctx, key=f"{ctx.key}|{physics.label()}", dt=physics.dt or ctx.dt,
        prefix=rescaled_pairs(ctx.prefix, ratio), stage_step=round(ctx.stage_step * ratio),
        playtest=None, physics=physics), ratio


def _noisy_passes(prep: _Prepared, ctx: Context, pairs: Pairs, end_step: int,
                  look_step: int, look_pairs: Pairs, noise, index: int) -> bool:
    """The simulated player's try ``index`` of the stage: its input moved by a person's
    error (``playtest.noise.perturb``), judged by the required terms. Every candidate
    gets the same draws (the same seed and try numbers): their rates compare hands
    alike, not luck."""
    from puppet.timeline.playtest.noise import perturb

    s0 = ctx.stage_step
    rel = [(s - s0, e) for s, e in pairs]
    setup = prep.session.setup
    slow = float(setup.interface.slowdown or 1.0)
    moved = perturb(rel, [slow] * len(rel), ctx.dt, end_step - s0, noise, ctx.seed,
                    index, setup.interface.app_key_table()).pairs
    traj, blowups = _play(prep, [(s + s0, e) for s, e in moved] + look_pairs, look_step)
    _, ok, _ = judge([t for t in ctx.terms if t.required], stretch(traj, ctx.t0), traj)
    return ok and not blowups


def stage_pairs(entries: list[dict], dt: float, mouse_from, end_step: int) -> Pairs:
    """A stage's script entries as (step, event) pairs, glides starting from
    ``mouse_from``; input after ``end_step`` is cut (the next stage owns that time)."""
    from puppet.timeline.script import ScriptSpec, compile_script

    spec = ScriptSpec.model_validate({"events": [{"t": 0.0, "mouse": list(mouse_from)}]
                                      + list(entries)})
    return [(s, e) for s, e in compile_script(spec, dt)[1:] if s <= end_step]

