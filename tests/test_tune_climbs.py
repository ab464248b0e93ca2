"""The ladder climbs as tuning specs (assets/tune/biped-ladder-climb.yaml,
biped-gymnast-climb-bound.yaml, -trot.yaml) and their candidate generators
(``key-turn``, ``grip-stroke``; the bound climb's one-key strokes are templates): each
gymnast spec's first tries are the shipped performance, entry for entry (the ladder's
are its keys in order: the shipped script presses them by watching), and the generators
write what their docstrings say."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest
import yaml

from puppet.timeline.tuning import Search, load_tune_spec
from puppet.timeline.tuning.candidates import complete
from puppet.timeline.tuning.generators import generate
from puppet.timeline.tuning.template import StageTemplate

ROOT = Path(__file__).resolve().parents[1]
DT = 1 / 480


def fake_session(t: float, held=()):
    """What a generator that only writes entries reads: the time and the grasps."""
    return SimpleNamespace(sim=SimpleNamespace(dt=DT, grasps={n: None for n in held}),
                           steps=round(t / DT))


def turn(values: dict, t0: float = 0.5):
    v = {"key": "g", "pre": "none", "pre_gap": 0.3, "post": "none", "post_gap": 0.5,
         "phase": 1.8, **values}
    return generate("key-turn", fake_session(t0), v, t0, round(10 / DT))


def test_key_turn_presses_the_optional_keys_and_ends_after_the_limbs_key():
    assert turn({}) == ([{"t": 0.51, "key": "g"}], 2.31)
    assert turn({"pre_gap": 0.7, "post_gap": 0.9}) == turn({})  # gaps of absent keys
    entries, end = turn({"pre": "u", "pre_gap": 0.7, "post": "h", "post_gap": 0.9, "key": "t"})
    assert entries == [{"t": 0.51, "key": "u"}, {"t": 1.21, "key": "t"},
                       {"t": 2.11, "key": "h"}]
    assert end == 3.01  # the stage is longer by the posture key's gap
    assert turn({"settle": 2.0})[1] == 4.31


def stroke(values: dict, held, t0: float = 2.0):
    v = {"x": 0.8, "y": 1.0, "duration": 0.6, "rearm_foot": 0.15, "rearm_hand": 0.35,
         "settle": 0.8, **values}
    return generate("grip-stroke", fake_session(t0, held), v, t0, round(10 / DT))


def test_grip_stroke_lets_go_only_of_what_holds_and_may_preload():
    hands = ("hand_near", "hand_far")
    feet = {"foot_near": 1, "foot_far": 1}
    entries, end = stroke(feet, held=hands)  # feet on the floor: only armed
    assert entries == [{"t": 2.01, "mouse": [0.8, 1.0], "over": 0.6},
                       {"t": 2.16, "key": "a"}, {"t": 2.16, "key": "s"}]
    assert end == 3.41
    entries, end = stroke({"hand_near": 1, "foot_far": 1, "preload": 1, "pre_y": 1.0},
                          held=hands + ("foot_near", "foot_far"))
    assert entries == [{"t": 2.01, "mouse": [0.8, 1.0], "over": 0.4},   # preload
                       {"t": 2.46, "key": "z"}, {"t": 2.46, "key": "s"},  # let go
                       {"t": 2.46, "mouse": [0.8, 1.0], "over": 0.6},
                       {"t": 2.61, "key": "s"}, {"t": 2.81, "key": "z"}]  # feet rearm first
    assert end == 3.86
    assert stroke({"hand_far": 1, "tail": 1.0}, held=hands)[1] == 4.41


def first_tries(name: str) -> tuple[list[dict], float]:
    """The performance a spec's first tries play, stage after stage (no physics: what
    holds is what the shipped climb holds - the hands from the start, the feet after
    their first stage)."""
    loaded = load_tune_spec(ROOT / "assets" / "tune" / f"{name}.yaml")
    spec = loaded.spec
    import msgspec

    out = [{k: list(v) if isinstance(v, tuple) else v for k, v in msgspec.to_builtins(e).items()
            if v is not None and not (k in ("over", "hold") and v == 0)} for e in spec.events]
    t = None
    for i, stage in enumerate(spec.stages):
        tpl = StageTemplate(loaded, i)
        if t is None:
            t = tpl.at({})
        params = complete(loaded.params[i], stage.first)
        fixed, length = tpl.entries(params, t)
        if stage.generator is None:  # a template (the bound climb's one-key strokes)
            entries, end = fixed, round(t + length, 4)
        else:
            held = ("hand_near", "hand_far") + (() if i == 0 else ("foot_near", "foot_far"))
            entries, end = generate(stage.generator, fake_session(t, held),
                                    tpl.values(params), t, round(60 / DT), fixed)
        out += [{"t": t, "action": "checkpoint"}] + entries
        t = end
    return sorted(out, key=lambda e: e["t"]), t


def test_the_ladder_climb_plays_the_specs_first_tries_keys_by_watching():
    """The shipped ladder climb presses the spec's keys in the spec's order, each by a
    rule a while after the catch before it (held.CHAIN), not on the spec's clock."""
    script = yaml.safe_load((ROOT / "assets" / "scripts" / "biped-ladder-climb.yaml").read_text())
    events, _ = first_tries("biped-ladder-climb")
    keys = [e["key"] for e in events if "key" in e]
    assert [e["key"] for e in script["events"]] + [r["key"] for r in script["rules"]] == keys
    assert all(r.get("times") == 1 for r in script["rules"])


@pytest.mark.parametrize("name", ["biped-gymnast-climb-bound", "biped-gymnast-climb-trot"])
def test_the_specs_first_tries_are_the_shipped_climb(name):
    script = yaml.safe_load((ROOT / "assets" / "scripts" / f"{name}.yaml").read_text())
    events, seconds = first_tries(name)
    assert seconds == script["seconds"]
    shipped = sorted(script["events"], key=lambda e: e["t"])
    assert [sorted(e.items()) for e in events] == [sorted(e.items()) for e in shipped]


def test_climbs_0_climbs_no_hill(tmp_path):
    text = (ROOT / "docs" / "tuning.md").read_text(encoding="utf-8")
    block = text.split("# file: assets/tune/luxo-first-hop.yaml\n")[1].split("```")[0]
    block = block.replace("search: {tries: 6, climbs: 1, refine: 10}",
                          "search: {tries: 3, climbs: 0, refine: 10}")
    path = tmp_path / "hop.yaml"
    path.write_text(block, encoding="utf-8")
    search = Search(load_tune_spec(path))
    search.run()
    assert 1 <= search.played <= 3  # its tries (a draw may repeat one), no climb


def test_a_stage_glides_on_from_the_point_an_entry_sent_the_mouse_to():
    """A glide's last step lands on its point only to the last bit; the next stage's
    first glide starts from the point itself, as the script compiler's does (else the
    written script and the searched run differ: the gymnast's climbs did)."""
    from puppet.timeline.tuning.search import _mouse_from

    last = {"type": "mouse", "x": 0.8993055555555556, "y": 0.30486111111111114}
    kept = [SimpleNamespace(entries=[{"t": 1.0, "mouse": [0.8993055555555556,
                                                          0.3048611111111111]}])]
    assert _mouse_from([(10, last)], [], kept) == (0.8993055555555556, 0.3048611111111111)
    assert _mouse_from([(10, last)], [], []) == (last["x"], last["y"])  # no entry: the event
    assert _mouse_from([], [], []) == (0.5, 0.5)
