"""What a playtest must see: a layout that holds poses forgives a novice's hands, and
the back flip as shipped on 2026-12-06 (one key press that must land on its step) does
not forgive a person's. The figures of every shipped log are in the feat table of docs/testing.md
(measured with ``puppet playtest assets/logs/*.jsonl --noise human``)."""

from __future__ import annotations

from pathlib import Path

from puppet.data.playtest import noise_at
from puppet.timeline.playtest import playtest

FIXTURES = Path(__file__).parent / "fixtures" / "playtest"


def test_a_layout_of_held_poses_passes_every_try_at_novice():
    """luxo-keys-sit-stand: sit (z), then stand slowly (v) - poses held for seconds,
    so +-60 ms of the key presses changes nothing that matters."""
    result = playtest("luxo-keys-sit-stand", noise_at("novice"), tries=20, seed=0)
    assert result.error is None
    assert result.passes == 20, [r.failed for r in result.results if not r.passed]


def test_the_fixed_back_flip_of_2026_12_fails_most_tries_at_human():
    """The copy of the biped back flip log and its interface (tests/fixtures/playtest/,
    kept as they were shipped): the flip needs its one press on the recorded step, and
    +-30 ms at slowdown 3 is +-4.8 steps, so only the tries that land on it pass (one in
    9.6 on average; seed 0 happens to land 5 of its 20)."""
    result = playtest(FIXTURES / "biped-backflip-2026-12.jsonl", noise_at("human"),
                      tries=20, seed=0)
    assert result.error is None and len(result.results) == 20
    assert result.passes <= 5, f"{result.passes}/20: the fixture's fragility is not seen"
    assert all(r.failed for r in result.results if not r.passed)  # each says what it missed
