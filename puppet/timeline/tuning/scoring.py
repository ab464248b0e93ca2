"""A try's score, from expectations and their margins (never from their words).

Each term is an expectation evaluated on the stage's stretch of the run (its times
counted from the stage's start) or on the whole run so far. It adds ``points`` if it
holds and ``weight`` times its margin, the margin counted from ``floor`` (a failure
with nothing to measure, -inf, counts as ``floor``) up to ``cap`` (past it, more is not
better). The spec's feat, judged on a stage, is terms of its own: each of its
expectations over the whole run, ``required``, 10 points, its margin up to 0.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from puppet.timeline.expectations import evaluate
from puppet.timeline.trajectory import Trajectory

BLOWUP_PENALTY = 1000.0  # a try whose physics blew up: below any other


@dataclass(frozen=True)
class Term:
    """A score term as the tries use it (``spec.TermSpec``, or a feat entry)."""

    expect: object  # an Expectation
    over: str = "stage"
    points: float = 10.0
    weight: float = 1.0
    cap: float = 0.0
    floor: float = -100.0
    required: bool = False
    feat: bool = False  # one of the spec's feat entries
    margin: float = 0.0  # what a required term's margin must reach

    @classmethod
    def of(cls, spec) -> Term:
        return cls(spec.expect, spec.over, spec.points, spec.weight, spec.cap, spec.floor,
                   spec.required, False, spec.margin)

    @classmethod
    def feat_entry(cls, e, required: bool = True) -> Term:
        return cls(e, "run", 10.0, 1.0, 0.0, -100.0, required, True)


@dataclass
class Judged:
    """One term's outcome: what the report shows and the resume file keeps."""

    kind: str
    passed: bool
    margin: float
    line: str
    required: bool
    feat: bool

    def to_list(self) -> list:
        return [self.kind, self.passed, None if not math.isfinite(self.margin)
                else self.margin, self.line, self.required, self.feat]

    @classmethod
    def from_list(cls, row: list) -> Judged:
        kind, passed, margin, line, required, feat = row
        return cls(kind, passed, -math.inf if margin is None else margin, line, required,
                   feat)


def stretch(traj: Trajectory, t0: float) -> Trajectory:
    """The samples from ``t0`` on, their times counted from it (positions unchanged)."""
    keep = traj.t >= t0 - 1e-9
    out = {}
    for f in dataclasses.fields(traj):
        value = getattr(traj, f.name)
        if isinstance(value, np.ndarray) and value.shape[:1] == traj.t.shape:
            value = value[keep]
        out[f.name] = value
    out["t"] = out["t"] - t0
    return Trajectory(**out)


def judge(terms: list[Term], stage: Trajectory, run: Trajectory,
          final_hash: str = "") -> tuple[float, bool, list[Judged]]:
    """(score, every required term held, each term's outcome)."""
    score, ok, judged = 0.0, True, []
    for term in terms:
        o = evaluate(term.expect, stage if term.over == "stage" else run, final_hash)
        margin = o.margin if o.margin is not None and not math.isnan(o.margin) else -math.inf
        counted = min(term.cap, max(term.floor, margin))
        score += term.points * o.passed + term.weight * counted
        if term.required and not (o.passed and margin >= term.margin):
            ok = False
        judged.append(Judged(o.kind, o.passed, margin, str(o), term.required, term.feat))
    return score, ok, judged
