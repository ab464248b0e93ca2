"""The stage-by-stage search from checkpoints (Laszlo et al. 2000, section 5: long
performances built segment by segment): for each stage in turn, a checkpoint where the
kept performance has got to, many tries of the stage from there, the best one kept.

A stage played ``times`` times (or ``until`` something holds) is a stage per
repetition, each from its own checkpoint: hop after hop. When no try of a stage meets
what it requires, the search backtracks: the stage before is replaced by its next-best
try (``alternatives`` are kept per stage) and the search goes on from there.

Each stage's tries are drawn in batches (``candidates``) and played by an executor
(``puppet.timeline.executor``: here, local processes, or a Dask cluster); the results
come back in the order asked, so the same spec and seed keep the same tries whatever
ran them. Every result is kept on disk (``state``): an interrupted search run again
looks its tries up and goes on.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from pathlib import Path

from puppet.interface import events as ev
from puppet.timeline.executor import Executor
from puppet.timeline.tuning.candidates import Climb, complete, draw, grid, rounds
from puppet.timeline.tuning.performer import merged
from puppet.timeline.tuning.scoring import Term
from puppet.timeline.tuning.spec import Loaded
from puppet.timeline.tuning.start import Start
from puppet.timeline.tuning.state import State, digest
from puppet.timeline.tuning.template import StageTemplate, r4
from puppet.timeline.tuning.trial import Context, Pairs, Task, TryResult, run_try, stage_pairs


class Interrupted(Exception):
    """The search stopped before its end (``stop_after`` tries, or Ctrl+C); what it
    played is in the state file, and running it again goes on from there."""


class Reporter:
    """What the search tells as it goes (the command shows it with tqdm); silent."""

    def stage(self, label: str, total: int) -> None:
        pass

    def advance(self, n: int = 1) -> None:
        pass

    def line(self, text: str) -> None:
        pass


@dataclass
class Kept:
    """A stage as kept: where it starts and ends, its values, its input."""

    stage: int
    rep: int
    t0: float
    end: float
    params: dict
    entries: list[dict]
    pairs: Pairs  # its checkpoint first
    result: TryResult
    alternatives: list = field(default_factory=list)  # (params, result), next best first
    interface_text: str | None = None


@dataclass
class TuneResult:
    kept: list[Kept]
    found: bool  # every stage kept a try that met its requirements, and the feat holds
    message: str
    pairs: Pairs  # the whole performance's input
    end_step: int
    seconds: float
    played: int = 0  # tries played by this run
    looked_up: int = 0  # tries found in the state file
    interface_text: str | None = None  # the interface as tuned (None: not varied)
    start: Start | None = None


def key(result: TryResult) -> tuple:
    return (result.accepted, result.score)


class Search:
    def __init__(self, loaded: Loaded, executor: Executor | None = None,
                 state_path: Path | None = None, reporter: Reporter | None = None,
                 stop_after: int | None = None, scale: float = 1.0,
                 seed: int | None = None):
        self.loaded = loaded
        self.spec = loaded.spec
        self.executor = executor or Executor()
        self.reporter = reporter or Reporter()
        self.stop_after = stop_after
        self.scale = scale
        self.seed = self.spec.seed if seed is None else seed
        self.start = Start(loaded)
        self.templates = [StageTemplate(loaded, i) for i in range(len(self.spec.stages))]
        self.terms = [self._terms(i) for i in range(len(self.spec.stages))]
        self.start.check_names(loaded, self.terms)
        # a try's result depends on the files played and this code (the fingerprint),
        # its stage's spec and the input before it (its key): a spec edited in a later
        # stage, another seed or budget still finds the tries it asks again
        self.state = State(state_path, self.start.fingerprint())
        if self.state.note:
            self.reporter.line(self.state.note)
        self.played = self.looked_up = 0

    def _terms(self, i: int) -> list[Term]:
        stage = self.spec.stages[i]
        terms = [Term.of(t) for t in stage.score]
        judged = stage.feat if stage.feat is not None else i == len(self.spec.stages) - 1
        if judged and self.spec.feat is not None:
            # a stage played again and again scores the feat but cannot be held to it
            # at every repetition: its 'until' (or the last time) decides
            gate = stage.times == 1 and not stage.until
            terms += [Term.feat_entry(e, gate) for e in self.spec.feat.expect]
        return terms

    def _stage_digest(self, si: int) -> str:
        """What a try's result depends on in the spec: its stage (and the feat, where
        the stage judges it)."""
        import msgspec

        stage = self.spec.stages[si]
        feat = any(t.feat for t in self.terms[si])
        return digest(msgspec.to_builtins(stage), [t.required for t in self.terms[si]],
                      msgspec.to_builtins(self.spec.feat) if feat else None,
                      msgspec.to_builtins(self.spec.mocap))

    def _scaled(self, n: int) -> int:
        return n if self.scale == 1.0 or n == 0 else max(1, round(n * self.scale))

    # -- one stage ---------------------------------------------------------------------
    def _context(self, si: int, rep: int, t0: float, kept: list[Kept]) -> Context:
        st = self.start
        s0 = round(t0 / st.dt)
        prefix = self._before(kept, s0) + [(s0, ev.action("checkpoint"))]
        stage = self.spec.stages[si]
        terms = self.terms[si]
        touches = any(type(t.expect.value).touches for t in terms) or any(
            type(e.value).touches for e in stage.until)
        playtest = None
        if stage.playtest is not None:
            from puppet.data.playtest import LEVELS

            p = stage.playtest
            playtest = (LEVELS[p.noise], self._scaled(p.tries), p.weight,
                        tuple(v.other() for v in p.physics))
        mouse = _mouse_from(prefix, self.spec.events, kept)
        ctx_key = digest(st.setup_from, st.dt, st.interval, prefix, self._stage_digest(si),
                         playtest and (playtest[1], playtest[2], self.seed))
        return Context(ctx_key, st.setup_from, st.dt, st.interval, prefix, s0, t0, terms,
                       list(stage.until), touches, playtest, self.seed, stage.generator,
                       mouse)

    def _task(self, ctx: Context, si: int, params: dict) -> tuple[Task, list[dict], float,
                                                                   str | None]:
        """The try of ``params``: its task, entries, end (s) and reloaded interface."""
        tpl, stage, st = self.templates[si], self.spec.stages[si], self.start
        entries, length = tpl.entries(params, ctx.t0)
        end = r4(ctx.t0 + length)
        end_step = round(end / st.dt)
        look_step = end_step + round(stage.lookahead / st.dt)
        text = st.interface_text(self.loaded.params[si], params)
        if stage.generator is not None:
            return (Task(ctx, [], end_step, look_step, [], tpl.values(params), entries),
                    entries, end, text)
        pairs = stage_pairs(entries, st.dt, ctx.mouse_from, end_step)
        look: Pairs = []
        span = end_step - ctx.stage_step
        for k in range(1, stage.lookahead_repeats + 1):
            look += [(s + k * span, e) for s, e in pairs if s + k * span <= look_step]
        if st.performer is not None:  # the clip plays along: its samples, merged
            pairs = merged(pairs, st.performer.between(ctx.stage_step, end_step))
            look = merged(look, st.performer.between(end_step, look_step + 1))
        if text is not None:
            pairs = [(ctx.stage_step, ev.reload(text))] + pairs
        return Task(ctx, pairs, end_step, look_step, look, tpl.values(params)), entries, \
            end, text

    def _evaluate(self, ctx: Context, si: int, batch: list[dict]) -> list[TryResult]:
        keys = [digest(ctx.key, p) for p in batch]
        out: list[TryResult | None] = [None] * len(batch)
        todo: list[int] = []
        asked: set[str] = set()
        for i, k in enumerate(keys):
            if k in asked:  # a try asked twice in one batch: played (or looked up) once
                self.reporter.advance(1)
                continue
            asked.add(k)
            if k in self.state.tries:
                out[i] = TryResult.from_dict(self.state.tries[k])
                self.looked_up += 1
                self.reporter.advance(1)
            else:
                todo.append(i)
        stop = False
        if self.stop_after is not None and self.played + len(todo) >= self.stop_after:
            todo = todo[:max(0, self.stop_after - self.played)]
            stop = True
        if todo:
            tasks = [self._task(ctx, si, batch[i])[0] for i in todo]
            results = self.executor.map(run_try, tasks, self.reporter.advance)
            for i, r in zip(todo, results, strict=True):
                self.state.tries[keys[i]] = r.to_dict()
                out[i] = r
            self.played += len(todo)
            self.state.save()
        if stop:
            raise Interrupted(f"stopped after {self.played} tries")
        for i, k in enumerate(keys):  # a try asked twice in one batch
            if out[i] is None:
                out[i] = TryResult.from_dict(self.state.tries[k])
        return out

    def _chunks(self, ctx: Context, si: int, batch: list[dict], pool: list) -> None:
        size = max(4, 4 * self.executor.workers)
        for i in range(0, len(batch), size):
            part = batch[i:i + size]
            for p, r in zip(part, self._evaluate(ctx, si, part), strict=True):
                pool.append((p, r))

    def _search_stage(self, si: int, rep: int, ctx: Context, label: str) -> list:
        """Every try of the stage, best first: (params, result), each params once."""
        stage = self.spec.stages[si]
        params = self.loaded.params[si]
        s = stage.search
        tries, refine = self._scaled(s.tries), self._scaled(s.refine)
        pool: list = []
        if not params:
            self.reporter.stage(label, 1)
            self._chunks(ctx, si, [{}], pool)
        elif s.grid:
            try:
                points = grid(params)
            except ValueError as exc:
                raise self.loaded.error(("stages", si, "vary"), str(exc)) from None
            self.reporter.stage(label, len(points))
            self._chunks(ctx, si, points, pool)
        else:
            self.reporter.stage(label, max(tries, 1) + s.climbs * refine)
            rng = random.Random(f"{self.seed}/{si}/{rep}")
            given = {**self.start.current(params), **stage.first}  # the interface's own
            first = complete(params, given) if given else None
            centre = first
            for r, n in enumerate(rounds(s, max(tries, 1))):
                batch = []
                if r == 0:
                    batch.append(first if first is not None else complete(params, {}))
                    n -= 1
                batch += [draw(params, rng, centre, s.around, s.sigma) for _ in range(n)]
                self._chunks(ctx, si, batch, pool)
                centre = max(pool, key=lambda item: key(item[1]))[0]
            for start in _distinct(sorted(pool, key=lambda i: key(i[1]), reverse=True),
                                   s.climbs):
                self._climb(ctx, si, params, start, refine, pool)
        return _distinct(sorted(pool, key=lambda i: key(i[1]), reverse=True), len(pool))

    def _climb(self, ctx, si, params, start, budget: int, pool: list) -> None:
        climb = Climb(params, start[0])
        current = start
        while budget > 0:
            near = climb.neighbours()[:budget]
            if not near:
                break
            found: list = []
            self._chunks(ctx, si, near, found)
            pool.extend(found)
            budget -= len(near)
            best = max(found, key=lambda item: key(item[1]))
            if key(best[1]) > key(current[1]):
                current = best
                climb.point = dict(best[0])
            elif not climb.shrink():
                break

    def _keep(self, ctx: Context, si: int, rep: int, params: dict, result: TryResult,
              alternatives: list) -> Kept:
        task, entries, end, text = self._task(ctx, si, params)
        pairs = task.pairs
        if self.spec.stages[si].generator is not None:
            entries = list(result.entries or [])
            if result.end is not None:
                end = result.end
            pairs = stage_pairs(entries, self.start.dt, ctx.mouse_from,
                                round(end / self.start.dt))
        return Kept(si, rep, ctx.t0, end, params, entries, ctx.prefix[-1:] + pairs, result,
                    alternatives, text)

    # -- the whole performance ---------------------------------------------------------
    def _before(self, kept: list[Kept], until: int | None = None) -> Pairs:
        """The input of the start and the kept stages (and, with ``mocap``, the clip's
        samples between a stage's end and a later start: up to step ``until``)."""
        st = self.start
        out = list(st.pairs)
        done = round(st.t0 / st.dt)
        for k in kept:
            if st.performer is not None:
                out += st.performer.between(done, round(k.t0 / st.dt))
                done = round(k.end / st.dt)
            out += k.pairs
        if st.performer is not None and until is not None:
            out += st.performer.between(done, until)
        return out

    def _label(self, si: int, rep: int) -> str:
        stage = self.spec.stages[si]
        many = stage.times > 1 or stage.until
        return f"stage {si + 1}/{len(self.spec.stages)} '{stage.name}'" + (
            f" #{rep + 1}" if many else "")

    def _t0(self, si: int, kept: list[Kept]) -> float:
        tpl = self.templates[si]
        previous = kept[-1].end if kept else self.start.t0
        if tpl.at is None or (kept and kept[-1].stage == si):
            return previous
        t0 = r4(tpl.at({}))
        if t0 < previous - 1e-9:
            raise self.loaded.error(("stages", si, "at"),
                                    f"the stage starts at {t0:g} s, before the performance "
                                    f"so far ends ({previous:g} s); expected 'at' at least "
                                    f"{previous:g}")
        return t0

    def _next(self, kept: list[Kept]) -> tuple[int, int] | str:
        """Where the search goes after ``kept``: (stage, repetition), or why it stops."""
        if not kept:
            return 0, 0
        last = kept[-1]
        stage = self.spec.stages[last.stage]
        if stage.until:
            if last.result.until_ok:
                return last.stage + 1, 0
            if last.rep + 1 < stage.times:
                return last.stage, last.rep + 1
            return (f"stage '{stage.name}': its 'until' still does not hold after "
                    f"{stage.times} times")
        if last.rep + 1 < stage.times:
            return last.stage, last.rep + 1
        return last.stage + 1, 0

    def run(self) -> TuneResult:
        kept: list[Kept] = []
        backtracks = 0
        message = ""
        found = True
        while True:
            where = self._next(kept)
            if isinstance(where, str):
                message, found = where, False
                break
            si, rep = where
            if si >= len(self.spec.stages):
                break
            t0 = self._t0(si, kept)
            ctx = self._context(si, rep, t0, kept)
            label = self._label(si, rep)
            tried = self._search_stage(si, rep, ctx, label)
            accepted = [item for item in tried if item[1].accepted]
            if accepted:
                best = accepted[0]
                alts = accepted[1:1 + self.spec.stages[si].alternatives]
                kept.append(self._keep(ctx, si, rep, best[0], best[1], alts))
                self._say(kept[-1], label)
                continue
            # backtrack: the latest stage that has another try to offer takes it
            back = max((i for i, k in enumerate(kept) if k.alternatives), default=None)
            if back is not None and backtracks < self.spec.max_backtracks:
                del kept[back + 1:]
                backtracks += 1
                k = kept.pop()
                params, result = k.alternatives[0]
                ctx_k = self._context(k.stage, k.rep, k.t0, kept)
                kept.append(self._keep(ctx_k, k.stage, k.rep, params, result,
                                       k.alternatives[1:]))
                self.reporter.line(f"{label}: no try met what it requires; back to "
                                   f"{self._label(k.stage, k.rep)}, its next best try")
                continue
            best = tried[0]
            kept.append(self._keep(ctx, si, rep, best[0], best[1], []))
            self._say(kept[-1], label)
            message = (f"{label}: no try met what it requires"
                       + (f" (after {backtracks} backtracks)" if backtracks else ""))
            found = False
            break
        pairs = self._before(kept)
        end = kept[-1].end if kept else self.start.t0
        if self.start.performer is not None:  # the command's samples at the last step too
            last = round(end / self.start.dt)
            pairs += self.start.performer.between(last, last + 1)
        last_feat = [j for j in kept[-1].result.judged if j.feat] if kept else []
        if found and any(not j.passed for j in last_feat):
            found, message = False, "the feat's expectations do not all hold"
        text = next((k.interface_text for k in reversed(kept) if k.interface_text), None)
        return TuneResult(kept, found, message, pairs, round(end / self.start.dt), end,
                          self.played, self.looked_up, text, self.start)

    def _say(self, k: Kept, label: str) -> None:
        r = k.result
        shown = ", ".join(f"{n} {v:g}" if not isinstance(v, str) else f"{n} {v}"
                          for n, v in k.params.items())
        rate = "" if r.pass_rate is None else f", playtest {r.pass_rate:.0%}"
        self.reporter.line(f"{label}: {k.t0:.2f}-{k.end:.2f} s, score {r.score:.2f}{rate}"
                           f"{'' if r.accepted else ' (misses what it requires)'}"
                           + (f"  [{shown}]" if shown else ""))
        for j in r.judged:
            self.reporter.line(f"    {j.line}")


def _mouse_from(prefix: Pairs, events: list, kept: list[Kept]) -> tuple[float, float]:
    """Where the mouse is at a stage's checkpoint, for the stage's first glide to start
    from: the last mouse event before it, or - when that is where an entry sent the
    mouse - the entry's own point. A glide's last step lands on its point only to the
    last bit of a float; the script compiler glides on from the point itself, so the
    written script and the searched run stay the same input."""
    mouse = (0.5, 0.5)
    for _, e in reversed(prefix):
        if e["type"] == "mouse":
            mouse = (e["x"], e["y"])
            break
    points = [tuple(e.mouse) for e in events if e.mouse is not None]
    points += [tuple(e["mouse"]) for k in kept for e in k.entries if "mouse" in e]
    for point in reversed(points):
        if max(abs(point[0] - mouse[0]), abs(point[1] - mouse[1])) < 1e-9:
            return (float(point[0]), float(point[1]))
    return mouse


def _distinct(items: list, n: int) -> list:
    """The first ``n`` of ``items`` with distinct parameters (none for ``n`` = 0)."""
    out, seen = [], set()
    if n <= 0:
        return out
    for params, result in items:
        mark = tuple(sorted(params.items()))
        if mark not in seen:
            seen.add(mark)
            out.append((params, result))
            if len(out) >= n:
                break
    return out


__all__ = ["Interrupted", "Kept", "Reporter", "Search", "TuneResult"]
