"""``puppet playtest --solver-passes N --step S``: a feat's pass rate on cheaper physics
(issue 29 chooses the physics settings by these figures). A try on other physics is the
same try as ``puppet replay --step``'s replay of it, the figures are not kept for the
HUD, and the settings reach the from-rest sweep too."""

from __future__ import annotations

import json

import pytest

from puppet.commands import main
from puppet.data.catalog import ROOT
from puppet.data.playtest import PARAMETERS, noise_at
from puppet.timeline.log import read_log
from puppet.timeline.other_physics import OtherPhysics
from puppet.timeline.playtest import prepare, run_try
from puppet.timeline.playtest.from_rest import failures, press_step
from puppet.timeline.replay import replay

STILL = noise_at("human", **{k: 0.0 for k in PARAMETERS if k != "stroke_gap_ms"})
LOG = ROOT / "assets" / "logs" / "luxo-hop.jsonl"


def test_prepare_moves_the_events_to_the_other_step_and_changes_the_solver():
    shipped = prepare("luxo-hop")
    coarse = prepare("luxo-hop", OtherPhysics(dt=1 / 240))
    assert float(shipped.log.header["dt"]) == 1 / 480 and coarse.log.header["dt"] == 1 / 240
    assert [e.step for e in coarse.log.events] == [round(e.step / 2)
                                                   for e in shipped.log.events]
    fewer = prepare("luxo-hop", OtherPhysics(iterations=36))
    assert fewer.setup.character.solver.iterations == 36
    assert shipped.setup.character.solver.iterations != 36
    assert prepare("luxo-hop") is shipped  # cached per physics


def test_a_try_without_noise_on_other_physics_is_replay_steps_replay():
    physics = OtherPhysics(iterations=36, dt=1 / 240)
    tried = run_try("luxo-hop", STILL, 0, 0, physics)
    replayed = replay(read_log(LOG), physics=physics)
    assert tried.final_hash == replayed.final_hash and tried.steps == replayed.steps
    assert tried.final_hash != run_try("luxo-hop", STILL, 0, 0).final_hash


def test_the_command_plays_on_other_physics_and_keeps_no_figures(monkeypatch, capsys):
    import puppet.timeline.playtest.store as store

    def refuse(*_a, **_k):
        raise AssertionError("figures on other physics are not the HUD's")

    monkeypatch.setattr(store, "save", refuse)
    code = main(["playtest", "luxo-hop", "--tries", "2", "--step", "1/240",
                 "--solver-passes", "36", "--json"])
    out = json.loads(capsys.readouterr().out)[0]
    assert code in (0, 1) and out["physics"] == "36 solver passes, a 1/240 s step"
    assert len(out["results"]) == 2 and out["bar"] is not None


@pytest.mark.parametrize("bad", ["1/10", "fast"])
def test_a_step_out_of_range_is_one_line(bad, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["playtest", "luxo-hop", "--step", bad, "--no-save"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert "argument --step" in err[-1] and "1/2000 to 1/30" in err[-1]


def test_the_from_rest_sweep_replays_on_the_other_physics():
    log = ROOT / "assets" / "logs" / "luxo-keys-sit-stand.jsonl"
    at = press_step(read_log(log), "z")
    assert failures((str(log), "z", at, OtherPhysics(dt=1 / 240))) == []
