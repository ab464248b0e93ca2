"""Every shipped ``playtest:`` bar, in a cheap version: a few tries at the bar's noise
level from seed 0 (the first of the tries ``puppet playtest`` runs: deterministic),
which must pass at the bar's rate less one try. A change that makes a forgiving feat
fragile fails here; ``puppet playtest assets/logs/*.jsonl`` measures the full bars."""

from __future__ import annotations

import math

import pytest

from puppet.data.catalog import ROOT
from puppet.data.playtest import noise_at
from puppet.timeline.log import read_log
from puppet.timeline.playtest import load_bar, playtest

TRIES, LONG_TRIES = 3, 2  # per bar (2 for a log over LONG steps): CPU, not coverage
LONG = 8000  # steps (16.7 s at 1/480 s); the full bars run 20 tries

LOGS = sorted((ROOT / "assets" / "logs").glob("*.jsonl"))
BARS = [(log, bar) for log in LOGS if (bar := load_bar(str(log))) is not None]


def test_some_shipped_feats_have_a_bar():
    assert len(BARS) >= 5, [log.stem for log, _ in BARS]


@pytest.mark.parametrize("log, bar", BARS, ids=[log.stem for log, _ in BARS])
def test_the_feat_still_clears_its_bar_in_a_few_tries(log, bar):
    """The bar's rate of the first tries of seed 0, less one try of margin."""
    tries = LONG_TRIES if read_log(log).last_step > LONG else TRIES
    result = playtest(log, noise_at(bar.noise), tries=tries, seed=0)
    assert result.error is None, result.error
    need = max(1, math.ceil(bar.min_pass * tries - 1e-9) - 1)
    missed = [f"try {r.index}: {'; '.join(r.failed)}" for r in result.results if not r.passed]
    assert result.passes >= need, (f"{log.stem}: {result.passes}/{tries} at {bar.noise} "
                                   f"(bar {bar.min_pass:.0%}): " + " | ".join(missed))
