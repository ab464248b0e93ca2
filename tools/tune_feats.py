"""Build Luxo's mouse feats stage by stage from checkpoints, scored by their own
expectations, and write each as a script and a sidecar expectations file.

    python tools/tune_feats.py FEAT [--tries 150] [--refine 60] [--seed 1]
                               [--write]   # assets/scripts/luxo-FEAT.yaml + expectations
    FEAT: shuffle, back-headspring, kip, headstand, double-backflip

A feat is a list of stages. Each stage is a mouse gesture (glides between mouse
positions, luxo-mouse coordinates: ankle target = 80 - 160 x deg, knee = 160 - 180 y
deg) with a few numbers to search. Before each stage the session checkpoints (the
script's ``checkpoint`` action, as the paper's users did), then tries gestures from
there - random ones within the stage's bounds, then a hill climb from the best
(tools/gestures.py) - and keeps the best. The score of a try is computed on the
trajectory the replay samples (``puppet.timeline.replay.Sampler``), history included:
every expectation of the feat (the very list written to its sidecar file) that passes
counts, and the stage adds graded terms on the same quantities so that the search
can climb towards them. A feat is found when every expectation holds. The checkpoint
actions stay in the script, so the recorded log replays straight through to the same
bits as the search saw.

Found and shipped (assets/logs/): shuffle (luxo-mouse; --seed 2 --tries 1500
--refine 300), back-headspring (luxo-mouse-strong; --seed 1 --tries 2500 --refine 300),
kip (luxo-mouse-strong; --seed 2 --tries 2500 --refine 300), headstand
(luxo-mouse-strong; --seed 1 --tries 1000 --refine 100: from lying on its back, pressed
up onto the shade, then balanced 0.3 s at a time, each piece chosen looking 0.5 s
ahead; no pose holds it statically: none of a 10-degree grid of poses stood on the
shade for 2 s untouched; the flip-based way up, headstand_feat(from_back=False),
reached 1.27 s at best). double-backflip (luxo-mouse-strong;
--explore --seed 7 --tries 2500: random gestures, every other one a perturbation of
the best so far; from the back flip's gesture the default search stays near one turn,
381 deg in flight at most).
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from puppet.data.catalog import ROOT  # noqa: E402
from puppet.session.playback import play  # noqa: E402
from puppet.timeline.expectations import evaluate_all, parse_expectations  # noqa: E402
from puppet.timeline.replay import SAMPLE_EVERY, Sampler  # noqa: E402
from tools.gestures import SessionRunner, climb, compile_entries  # noqa: E402

STAND = (0.656, 0.583)  # the start pose in luxo-mouse coordinates


def tilt(angle: np.ndarray) -> np.ndarray:
    return np.abs(np.degrees(np.remainder(angle + np.pi, 2 * np.pi) - np.pi))


class FeatRunner(SessionRunner):
    """A Session, a Sampler over its whole history, checkpoints to try stages from."""

    def __init__(self, interface: str, scene: str):
        super().__init__(interface, scene)
        self.sampler = Sampler(self.session)
        self.sampler(self.session)
        self.mark = 0

    def run(self, entries: list[dict], until: float, mouse_from=STAND):
        pairs = compile_entries(entries, self.dt, mouse_from)
        play(self.session, pairs, self.steps(until), SAMPLE_EVERY, self.sampler)
        return self.sampler.trajectory()


@dataclass
class Stage:
    """One searched gesture: ``entries(t0, p)`` gives its script entries and when it
    ends; ``score(traj, t0, passed)`` grades a try (``passed``: how many of the feat's
    expectations hold, counted only on the last stage)."""

    name: str
    bounds: dict
    entries: object
    score: object
    seed: dict | None = None
    last: bool = False
    lookahead: float = 0.0  # s run past the stage's end when scoring a try (not kept)


@dataclass
class Feat:
    interface: str
    scene: str
    description: str
    expect: list
    stages: list[Stage]
    expect_description: str = ""
    notes: list[str] = field(default_factory=list)


def glide(t: float, xy, over: float) -> dict:
    r = lambda v: round(float(v), 4)  # noqa: E731
    return {"t": r(t), "mouse": [r(xy[0]), r(xy[1])], "over": r(max(over, 0.0))}


# -- the feats -----------------------------------------------------------------------
def _steps(traj, t0):
    """Indices of samples from ``t0`` on."""
    return np.flatnonzero(traj.t >= t0 - 1e-9)


def shuffle_feat() -> Feat:
    seconds = 12.0  # the step is repeated for this long

    def entries(t0, p):
        out, t = [], t0
        while t < t0 + seconds:
            out.append(glide(t, (p["ax"], p["ay"]), p["a_over"]))
            t += p["a_over"] + p["a_hold"]
            out.append(glide(t, (p["bx"], p["by"]), p["b_over"]))
            t += p["b_over"] + p["b_hold"]
        out.append(glide(t, STAND, 0.3))
        return out, t + 1.0

    def score(traj, t0, passed):
        base = traj.index("base")
        free = ~traj.contact[:, base]
        from puppet.timeline.expectations import _longest_run
        longest = _longest_run(free, traj.t)[0]
        dx = traj.x[-1, base] - traj.x[0, base]
        ground_tilt = np.where(traj.contact.any(axis=1), tilt(traj.root_angle), 0).max()
        return (passed * 10 + min(dx, 0.8) * 8 - 60 * max(0.0, longest - 0.075)
                - 0.2 * max(0.0, ground_tilt - 25) - 0.2 * tilt(traj.root_angle[-1:])[0])

    bounds = {"ax": (0.45, 1.0), "ay": (0.2, 0.8), "a_over": (0.03, 0.3), "a_hold": (0.0, 0.3),
              "bx": (0.2, 0.8), "by": (0.2, 0.8), "b_over": (0.03, 0.3), "b_hold": (0.0, 0.3)}
    seed = {"ax": 0.85, "ay": 0.5, "a_over": 0.1, "a_hold": 0.1,
            "bx": 0.5, "by": 0.6, "b_over": 0.1, "b_hold": 0.1}
    return Feat("luxo-mouse", "flat",
                "A shuffle on the mouse: small rocking steps forward, the base never off the "
                "floor for long.",
                [{"x_at_end": {"link": "base", "min": 0.5}},
                 {"airborne": {"link": "base", "max_seconds": 0.1}},
                 {"upright_at_end": True}, {"never_fell": True}],
                [Stage("shuffle", bounds, entries, score, seed, last=True)],
                "A shuffle on the mouse (luxo-mouse, flat): the same small rocking step, "
                f"repeated for {seconds:g} s, moves Luxo at least 0.5 m forward without the "
                "base ever leaving the floor for more than 0.1 s, upright.")


def _flip_entries(p, t0):
    """stand -> crouch -> flick to the push pose -> tuck -> open -> stand."""
    t_crouch = t0 + 0.05
    t_push = t_crouch + 0.15 + p["hold"]
    t_tuck = t_push + p["flick"] + p["tuck_at"]
    t_open = t_tuck + 0.05 + p["open_at"]
    return [glide(t_crouch, (p["cx"], p["cy"]), 0.15),
            glide(t_push, (p["px"], p["py"]), p["flick"]),
            glide(t_tuck, (p["tx"], p["ty"]), 0.05),
            glide(t_open, (p["lx"], p["ly"]), p.get("open_over", 0.1)),
            glide(t_open + p.get("stand_at", 0.6), STAND, 0.3)], t_open + 1.8


FLIP_BOUNDS = {
    "cx": (0.0, 1.0), "cy": (0.0, 0.5), "hold": (0.2, 0.8),
    "px": (0.0, 0.6), "py": (0.4, 1.0), "flick": (0.01, 0.1),
    "tuck_at": (0.0, 0.3), "tx": (0.0, 1.0), "ty": (0.0, 0.6),
    "open_at": (0.05, 0.8), "lx": (0.2, 0.9), "ly": (0.2, 0.8),
}
BACKFLIP = {"cx": 1.0, "cy": 0.0529, "hold": 0.3394, "px": 0.3342, "py": 0.4644,
            "flick": 0.0177, "tuck_at": 0.1332, "tx": 0.2624, "ty": 0.1548,
            "open_at": 0.4363, "lx": 0.8006, "ly": 0.5685}  # assets/scripts/luxo-backflip


def _turn(traj, link="base"):
    return np.degrees(np.unwrap(traj.angle[:, traj.index(link)]))


def _flight_turn(traj):
    from puppet.timeline.expectations import _runs
    turn = _turn(traj)
    free = ~traj.contact.any(axis=1)
    best = 0.0
    for i, j in _runs(free):
        a, b = max(i - 1, 0), min(j + 1, len(free) - 1)
        best = max(best, float(turn[b] - turn[a]))
    return best


def double_backflip_feat(interface="luxo-mouse-strong") -> Feat:
    def score(traj, t0, passed):
        turned = _turn(traj)[-1] - _turn(traj)[0]
        ground = np.where(traj.contact.any(axis=1), tilt(traj.root_angle), 0)
        return (passed * 100 - abs(turned - 720) + 0.5 * min(_flight_turn(traj), 720)
                - 2.0 * min(100.0, max(0.0, ground.max() - 60))
                - 1.0 * min(90.0, tilt(traj.root_angle[-1:])[0]))

    bounds = dict(FLIP_BOUNDS, open_at=(0.1, 1.2))
    return Feat(interface, "flat",
                "A double back flip on the mouse - crouch, flick up and back, tuck hard, "
                "open, land upright.",
                [{"turned": {"link": "base", "min_degrees": 690, "direction": "backward"}},
                 {"turned": {"link": "base", "min_degrees": 600, "direction": "backward",
                             "in_flight": True}},
                 {"upright_at_end": True}, {"never_fell": True}],
                [Stage("double flip", bounds, lambda t0, p: _flip_entries(p, t0), score,
                       BACKFLIP, last=True)],
                f"A double back flip on the mouse ({interface}, flat): two full backward "
                "turns, at least 600 deg of them in one flight, landing upright on the base.")


def back_headspring_feat(interface="luxo-mouse-strong") -> Feat:
    expect = [{"turned": {"link": "base", "min_degrees": 300, "direction": "backward"}},
              {"stood_on": {"link": "upper_arm", "min_seconds": 0.02, "min_tilt": 120}},
              {"upright_at_end": True}]

    def score(traj, t0, passed):
        turned = _turn(traj)[-1] - _turn(traj)[0]
        k = traj.index("upper_arm")
        others = np.delete(traj.contact, k, axis=1).any(axis=1)
        inverted = tilt(traj.root_angle) >= 120
        shade_only = (traj.contact[:, k] & ~others & inverted).sum()
        bad = (others & inverted).sum()  # inverted on something other than the shade
        return (passed * 100 - abs(turned - 360) + 3 * min(shade_only, 10) - 2 * bad
                - 1.0 * min(90.0, tilt(traj.root_angle[-1:])[0]))

    return Feat(interface, "flat",
                "A back headspring on the mouse - over backwards onto the shade and back onto "
                "the base.",
                expect,
                [Stage("headspring", FLIP_BOUNDS, lambda t0, p: _flip_entries(p, t0), score,
                       BACKFLIP, last=True)],
                f"A back headspring on the mouse ({interface}, flat): from standing Luxo goes "
                "over backwards, touches down on its shade alone with the base up, and comes "
                "back over onto its base, upright: a full backward turn.")


def fall_on_back_stage() -> Stage:
    """Lean back until Luxo falls on its back, then lie still."""
    def fall_entries(t0, p):
        return [glide(t0 + 0.05, (p["fx"], p["fy"]), p["f_over"]),
                glide(t0 + 0.05 + p["f_over"] + 0.6, (p["rx"], p["ry"]), 0.3)], t0 + 2.5

    def fall_score(traj, t0, passed):
        idx = _steps(traj, t0 + 1.2)
        lying = tilt(traj.root_angle[idx]) >= 80
        moving = np.abs(np.diff(traj.root_angle[idx])).sum()
        return lying.mean() * 10 - moving

    fall_bounds = {"fx": (0.0, 0.3), "fy": (0.4, 1.0), "f_over": (0.05, 0.4),
                   "rx": (0.2, 0.8), "ry": (0.3, 0.8)}
    fall_seed = {"fx": 0.0, "fy": 0.9, "f_over": 0.2, "rx": 0.656, "ry": 0.583}
    return Stage("fall on its back", fall_bounds, fall_entries, fall_score, fall_seed)


def kip_feat(interface="luxo-mouse-strong") -> Feat:
    expect = [{"got_up": {"lay_seconds": 1.0, "within_seconds": 0.8}},
              {"upright_at_end": True}]

    def kip_entries(t0, p):
        t1 = t0 + 0.05
        t2 = t1 + p["a_over"] + p["a_hold"]
        t3 = t2 + p["b_over"] + p["b_hold"]
        return [glide(t1, (p["ax"], p["ay"]), p["a_over"]),
                glide(t2, (p["bx"], p["by"]), p["b_over"]),
                glide(t3, (p["cx"], p["cy"]), p["c_over"]),
                glide(t3 + p["c_over"] + 0.3, STAND, 0.3)], t3 + 2.2

    def kip_score(traj, t0, passed):
        idx = _steps(traj, t0)
        tl = tilt(traj.root_angle[idx])
        return passed * 100 - tl[-1] - 0.3 * tl[-len(tl) // 3:].mean()

    kip_bounds = {"ax": (0.0, 1.0), "ay": (0.0, 1.0), "a_over": (0.01, 0.3),
                  "a_hold": (0.0, 0.5), "bx": (0.0, 1.0), "by": (0.0, 1.0),
                  "b_over": (0.01, 0.3), "b_hold": (0.0, 0.5), "cx": (0.0, 1.0),
                  "cy": (0.0, 1.0), "c_over": (0.01, 0.3)}
    kip_seed = {"ax": 0.22, "ay": 0.33, "a_over": 0.05, "a_hold": 0.3, "bx": 0.2, "by": 0.33,
                "b_over": 0.05, "b_hold": 0.3, "cx": 0.6, "cy": 0.6, "c_over": 0.1}
    return Feat(interface, "flat",
                "A kip on the mouse - Luxo leans back until it falls on its back, lies still, "
                "then gets up onto its base in one motion.",
                expect,
                [fall_on_back_stage(),
                 Stage("kip", kip_bounds, kip_entries, kip_score, kip_seed, last=True)],
                f"A kip on the mouse ({interface}, flat): Luxo throws itself on its back and "
                "lies there (root at least 80 deg from upright) for more than a second, then "
                "gets up onto its base in one motion, standing within 0.8 s.")


def headstand_feat(interface="luxo-mouse-strong", from_back: bool = True) -> Feat:
    expect = [{"stood_on": {"link": "upper_arm", "min_seconds": 2.0, "min_tilt": 135}},
              {"upright_at_end": True}]
    hold_pieces, piece = 20, 0.3  # s each; each tried looking 0.5 s further

    def up_entries(t0, p):
        e, _ = _flip_entries(p, t0)
        return e[:4], t0 + 0.05 + 0.15 + p["hold"] + p["flick"] + p["tuck_at"] + 0.05 \
            + p["open_at"] + 0.3

    def on_shade(traj, idx):
        k = traj.index("upper_arm")
        others = np.delete(traj.contact, k, axis=1).any(axis=1)
        return traj.contact[idx, k] & ~others[idx] & (tilt(traj.root_angle[idx]) >= 135)

    def up_score(traj, t0, passed):
        idx = _steps(traj, t0)
        last = idx[-len(idx) // 5:]
        return 10 * on_shade(traj, last).mean() - 0.05 * abs(180 - tilt(
            traj.root_angle[last])).mean() - 5 * np.abs(np.diff(traj.root_angle[last])).sum()

    def hold_entries(t0, p):
        return [glide(t0, (p["x"], p["y"]), p["over"])], t0 + piece

    def hold_score(traj, t0, passed):
        idx = _steps(traj, t0)
        look = _steps(traj, t0 + piece)
        kept = np.setdiff1d(idx, look)
        end = look[:6]  # the kept piece's last moment
        # the stretch must not break inside the kept piece; the lookahead says whether
        # it can go on from where the piece leaves it
        return (10 * on_shade(traj, kept).all() + 5 * on_shade(traj, look).mean()
                - 0.05 * abs(180 - tilt(traj.root_angle[end])).mean()
                - 5 * np.abs(np.diff(traj.root_angle[end])).sum())

    def down_entries(t0, p):
        return [glide(t0, (p["ax"], p["ay"]), p["a_over"]),
                glide(t0 + p["a_over"] + p["a_hold"], (p["bx"], p["by"]), p["b_over"]),
                glide(t0 + p["a_over"] + p["a_hold"] + p["b_over"] + 0.4, STAND, 0.3)], \
            t0 + p["a_over"] + p["a_hold"] + p["b_over"] + 2.0

    def down_score(traj, t0, passed):
        idx = _steps(traj, t0)
        return passed * 100 - tilt(traj.root_angle[idx[-1:]])[0]

    # a glide ends within its piece: the script would go on gliding into the next one
    hold_bounds = {"x": (0.0, 1.0), "y": (0.0, 1.0), "over": (0.02, piece - 0.02)}
    down_bounds = {"ax": (0.0, 1.0), "ay": (0.0, 1.0), "a_over": (0.02, 0.3),
                   "a_hold": (0.0, 0.4), "bx": (0.0, 1.0), "by": (0.0, 1.0),
                   "b_over": (0.02, 0.3)}
    def push_entries(t0, p):  # from lying on its back: press the base up over the shade
        t1 = t0 + 0.05
        t2 = t1 + p["a_over"] + p["a_hold"]
        return [glide(t1, (p["ax"], p["ay"]), p["a_over"]),
                glide(t2, (p["bx"], p["by"]), p["b_over"])], t2 + p["b_over"] + 0.3

    push_bounds = {"ax": (0.0, 1.0), "ay": (0.0, 1.0), "a_over": (0.05, 1.0),
                   "a_hold": (0.0, 0.5), "bx": (0.0, 1.0), "by": (0.0, 1.0),
                   "b_over": (0.05, 1.0)}
    if from_back:
        stages = [fall_on_back_stage(),
                  Stage("push up onto the shade", push_bounds, push_entries, up_score)]
    else:
        stages = [Stage("onto the shade", FLIP_BOUNDS, up_entries, up_score, BACKFLIP)]
    stages += [Stage(f"balance {i + 1}", hold_bounds, hold_entries, hold_score,
                     lookahead=0.5) for i in range(hold_pieces)]
    stages.append(Stage("down", down_bounds, down_entries, down_score, last=True))
    return Feat(interface, "flat",
                "A headstand on the mouse - up onto the shade, base up, balance, then down onto "
                "the base.",
                expect, stages,
                f"A headstand on the mouse ({interface}, flat): Luxo goes over backwards onto "
                "its shade and balances there alone, base up (root at least 135 deg from "
                "upright), for at least 2 s, then comes back down to standing on its base.")


FEATS = {"shuffle": shuffle_feat, "double-backflip": double_backflip_feat,
         "back-headspring": back_headspring_feat, "kip": kip_feat, "headstand": headstand_feat}


# -- the search ----------------------------------------------------------------------
def build(feat: Feat, tries: int, refine: int, seed: int, budget_s: float,
          given: list[dict] | None = None, explore: bool = False):
    """Search every stage (or play the ``given`` parameters, one dict per stage, as a
    search printed them); the script entries, the end time and the last outcomes."""
    rng = random.Random(seed)
    items = parse_expectations(feat.expect).items
    runner = FeatRunner(feat.interface, feat.scene)
    script = [{"t": 0.0, "mouse": list(STAND)}]
    t0 = 0.3
    runner.run(script, t0)  # the script's first event too: the same bits as the recording
    started = time.time()
    outcomes = []
    for stage in feat.stages:
        runner.checkpoint()
        script.append({"t": round(t0, 4), "action": "checkpoint"})
        mouse_from = last_mouse(script)

        def evaluate(p, stage=stage, t0=t0, mouse_from=mouse_from):
            runner.back()
            # rounded as printed: --params with the printed numbers gives the same bits
            ents, end = stage.entries(t0, {k: round(v, 4) for k, v in p.items()})
            traj = runner.run(ents, round(end, 4) + stage.lookahead, mouse_from)
            outs = evaluate_all(items, traj, "") if stage.last else []
            passed = sum(o.passed for o in outs)
            return (stage.score(traj, t0, passed), passed, outs)

        def score(o):
            return o[0]

        pool = []
        if given is not None:
            p = given[feat.stages.index(stage)]
            o = evaluate(p)
            pool, tries, refine = [(o[0], p, o)], 0, 0
        best = None  # explore: every other try perturbs the best so far
        for i in range(tries):
            if explore:
                if best is not None and i % 2:
                    p = {k: min(hi, max(lo, best[k] + rng.gauss(0, 0.1 * (hi - lo))))
                         for k, (lo, hi) in stage.bounds.items()}
                else:
                    p = {k: rng.uniform(lo, hi) for k, (lo, hi) in stage.bounds.items()}
                o = evaluate(p)
                if not pool or o[0] > max(q[0] for q in pool):
                    best = p
                pool.append((o[0], p, o))
                continue
            if i == 0 and stage.seed is not None:
                p = dict(stage.seed)
            elif stage.seed is not None and i % 2:
                p = {k: min(hi, max(lo, stage.seed[k] + rng.gauss(0, 0.15 * (hi - lo))))
                     for k, (lo, hi) in stage.bounds.items()}
            else:
                p = {k: rng.uniform(lo, hi) for k, (lo, hi) in stage.bounds.items()}
            o = evaluate(p)
            pool.append((o[0], p, o))
            if time.time() - started > budget_s:
                break
        pool.sort(key=lambda item: -item[0])
        best_s, best_p, best_o = pool[0]
        # climb from the best (explore: from the best three, until one passes)
        for s0, p0, o0 in pool[:(3 if explore else 1) if refine else 0]:
            s1, p1, o1 = climb(evaluate, score, stage.bounds, s0, p0, o0, refine)
            if s1 > best_s:
                best_s, best_p, best_o = s1, p1, o1
            if stage.last and all(o.passed for o in best_o[2]):
                break
        ents, end = stage.entries(t0, {k: round(v, 4) for k, v in best_p.items()})
        end = round(end, 4)  # as the script writes the next checkpoint's time
        runner.back()
        runner.run(ents, end, mouse_from)
        script += ents
        outcomes = best_o[2]
        print(f"{stage.name}: score {best_s:.2f}  [{time.time() - started:.0f} s]  "
              f"{json.dumps({k: round(v, 4) for k, v in best_p.items()})}", flush=True)
        for o in outcomes:
            print(f"  {o}")
        t0 = end
    return script, t0, outcomes


def last_mouse(script: list[dict]):
    for e in reversed(script):
        if "mouse" in e:
            return tuple(e["mouse"])
    return STAND


def write_files(name: str, feat: Feat, script: list[dict], seconds: float) -> None:
    import yaml

    path = ROOT / "assets" / "scripts" / f"luxo-{name}.yaml"
    lines = [f"description: {json.dumps(feat.description)}",
             "# Built by tools/tune_feats.py stage by stage from checkpoints, scored by the",
             f"# expectations in assets/logs/luxo-{name}.expect.yaml.",
             f"interface: {feat.interface}", f"scene: {feat.scene}",
             f"seconds: {round(seconds, 3)}", "events:"]
    for e in script:
        body = ", ".join(f"{k}: {v}" for k, v in e.items() if not (k == "over" and v == 0))
        lines.append(f"  - {{{body}}}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    side = ROOT / "assets" / "logs" / f"luxo-{name}.expect.yaml"
    side.write_text(yaml.safe_dump({"description": feat.expect_description,
                                    "expect": feat.expect}, sort_keys=False, width=88),
                    encoding="utf-8")
    print(f"wrote {path} and {side}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("feat", choices=sorted(FEATS))
    ap.add_argument("--interface", help="another interface than the feat's")
    ap.add_argument("--tries", type=int, default=150, help="random gestures per stage")
    ap.add_argument("--refine", type=int, default=60, help="hill-climb tries per stage")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--budget", type=float, default=600.0, help="s of random tries in all")
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--explore", action="store_true",
                    help="random tries alternate with perturbations of the best so far "
                         "(not of the stage's seed)")
    ap.add_argument("--params", help="JSON list, one dict per stage: play these (as a "
                                     "search printed them) instead of searching")
    args = ap.parse_args(argv)
    feat = FEATS[args.feat](args.interface) if args.interface else FEATS[args.feat]()
    given = json.loads(args.params) if args.params else None
    script, seconds, outcomes = build(feat, args.tries, args.refine, args.seed, args.budget,
                                      given, args.explore)
    found = outcomes and all(o.passed for o in outcomes)
    print("FOUND" if found else "not found")
    if args.write and found:
        write_files(args.feat, feat, script, seconds)
    return 0 if found else 1


if __name__ == "__main__":
    sys.exit(main())
