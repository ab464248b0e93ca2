"""Luxo's mouse feats (issue 15): each log fails named expectations when the interface
or the physics is weakened, and the expectations they use measure what they say."""

from __future__ import annotations

import json
import shutil
from functools import cache
from pathlib import Path

import pytest
import yaml

from puppet.data.catalog import ROOT, find
from puppet.testing import check, replay_log

LOGS = ROOT / "assets" / "logs"


@cache
def replayed(name: str):
    return replay_log(str(LOGS / f"{name}.jsonl"))


def _weakened(name: str, tmp_path: Path, *, servos: float = 1.0, friction: float = 1.0,
              gravity: float = 1.0) -> Path:
    """A copy of the log (and its sidecar) replaying against a weakened copy of its
    interface (servo stiffness and torque times ``servos``) and scene (friction and
    gravity times the factors)."""
    log = LOGS / f"{name}.jsonl"
    lines = log.read_text(encoding="utf-8").splitlines(keepends=True)
    head = json.loads(lines[0])
    iface = yaml.safe_load(find("interface", head["interface"]).read_text(encoding="utf-8"))
    for gains in iface.get("gains", {}).values():
        gains["stiffness"] *= servos
        gains["max_torque"] *= servos
    iface["name"] += "-weak"
    scene = yaml.safe_load(find("scene", head["scene"]).read_text(encoding="utf-8"))
    for g in scene["ground"]:
        g["friction"] = g.get("friction", 0.8) * friction
    scene["gravity"] = [v * gravity for v in scene.get("gravity", [0.0, -9.81])]
    scene["name"] += "-weak"
    iface["scene"] = str(tmp_path / "scene-weak.yaml")
    (tmp_path / "scene-weak.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    ipath = tmp_path / "iface-weak.yaml"
    ipath.write_text(yaml.safe_dump(iface), encoding="utf-8")
    head.update(interface=str(ipath), interface_text=ipath.read_text(encoding="utf-8"),
                scene=str(tmp_path / "scene-weak.yaml"))
    out = tmp_path / log.name
    out.write_text(json.dumps(head) + "\n" + "".join(lines[1:]), encoding="utf-8")
    shutil.copy(LOGS / f"{name}.expect.yaml", tmp_path / f"{name}.expect.yaml")
    return out


def _failed(path: Path) -> set[str]:
    result = replay_log(path)
    return {o.expectation.split()[0].rstrip(":") for o in result.failed} - {"same"}


# -- shuffle --------------------------------------------------------------------------
def test_shuffle_moves_half_a_metre_without_hopping():
    result = replayed("luxo-shuffle")
    assert not result.failed, [str(o) for o in result.failed]
    # a hop would fail the shuffle's airborne limit; the shuffle fails a hop's flight
    assert check(replayed("luxo-hop"), [{"airborne": {"link": "base", "max_seconds": 0.1}}])
    assert check(result, [{"airborne": {"link": "base", "min_seconds": 0.1}}])
    # ... and its steps do leave the floor a little (0.05 s at most since the fold ends
    # on the kick's lift, issue 29: 0.083 s before)
    assert check(result, [{"airborne": {"link": "base", "max_seconds": 0.04}}])


@pytest.mark.parametrize("weaker", [{"friction": 0.2}, {"servos": 0.6}])
def test_shuffle_fails_on_a_slippery_floor_or_with_weaker_servos(tmp_path, weaker):
    # (since its steps wait for the base to be level, it still shuffles 0.5 m at 0.3 of
    # the floor's friction)
    assert "x_at_end" in _failed(_weakened("luxo-shuffle", tmp_path, **weaker))


# -- back headspring -------------------------------------------------------------------
def test_back_headspring_touches_down_on_the_shade_alone_upside_down():
    result = replayed("luxo-back-headspring")
    assert not result.failed, [str(o) for o in result.failed]
    # the back flip turns as far but never puts its shade down upside down
    flip = replayed("luxo-backflip")
    assert check(flip, [{"stood_on": {"link": "upper_arm", "min_seconds": 0.02,
                                      "min_tilt": 120}}])


def test_back_headspring_fails_with_weaker_servos(tmp_path):
    failed = _failed(_weakened("luxo-back-headspring", tmp_path, servos=0.6))
    assert failed & {"turned", "stood_on", "upright_at_end"}, failed


# -- kip ---------------------------------------------------------------------------------
def test_kip_lies_on_its_back_then_gets_up_in_one_motion():
    result = replayed("luxo-kip")
    assert not result.failed, [str(o) for o in result.failed]
    # a hop never lies down; the kip does not get up fast enough for a tighter limit
    assert check(replayed("luxo-hop"), [{"got_up": {"lay_seconds": 1.0,
                                                    "within_seconds": 0.8}}])
    assert check(result, [{"got_up": {"lay_seconds": 1.0, "within_seconds": 0.3}}])


@pytest.mark.parametrize("weaker", [{"servos": 0.6}, {"gravity": 1.5}])
def test_kip_fails_with_weaker_servos_or_stronger_gravity(tmp_path, weaker):
    # (luxo-kip's states still get the lamp onto its base then - at 0.4 of the servos'
    # strength too - but by a roll, without the push up on the shade that lifts the base
    # 12 cm: the kip is that push)
    assert "reached_height" in _failed(_weakened("luxo-kip", tmp_path, **weaker))


# -- headstand ---------------------------------------------------------------------------
def test_headstand_balances_on_the_shade_for_two_seconds_then_stands():
    result = replayed("luxo-headstand")
    assert not result.failed, [str(o) for o in result.failed]
    # balanced 3.4 s, until the player's flick down (the layout holds it as long as asked)
    assert check(result, [{"stood_on": {"link": "upper_arm", "min_seconds": 4.5}}])
    # the back headspring only touches down on its shade
    assert check(replayed("luxo-back-headspring"),
                 [{"stood_on": {"link": "upper_arm", "min_seconds": 2.0}}])


@pytest.mark.parametrize("weaker", [{"servos": 0.8}, {"gravity": 1.2}])
def test_headstand_fails_with_weaker_servos_or_stronger_gravity(tmp_path, weaker):
    assert "stood_on" in _failed(_weakened("luxo-headstand", tmp_path, **weaker))


# -- double back flip ---------------------------------------------------------------------
def test_double_back_flip_turns_twice_in_one_flight_and_lands_upright():
    result = replayed("luxo-double-backflip")
    assert not result.failed, [str(o) for o in result.failed]
    # the single back flip fails the double's turns; the double is not a triple
    assert len(check(replayed("luxo-backflip"), [
        {"turned": {"link": "base", "min_degrees": 690}},
        {"turned": {"link": "base", "min_degrees": 600, "in_flight": True}}])) == 2
    assert check(result, [{"turned": {"link": "base", "min_degrees": 1000}}])


@pytest.mark.parametrize("weaker", [{"servos": 0.6}, {"gravity": 2.0}])
def test_double_back_flip_fails_with_weaker_servos_or_stronger_gravity(tmp_path, weaker):
    # Since the opening follows the flight time left (issue 28: com.fall_time), the flip
    # lands with a fifth less servo strength, and with gravity up to 1.7 times (the loop
    # reads the scene's gravity): it was an open-loop knife edge that fell at 0.8 and 1.2.
    # At 0.6 the spring and the tuck are too weak to turn twice, and at twice the gravity
    # the flight is too short: it turns short and ends on its side.
    failed = _failed(_weakened("luxo-double-backflip", tmp_path, **weaker))
    assert {"turned", "upright_at_end"} <= failed, failed


# -- the new expectation kinds are validated ---------------------------------------------
@pytest.mark.parametrize("entry, message", [
    ({"airborne": {"link": "base"}}, "give 'min_seconds', 'max_seconds' or both"),
    ({"stood_on": {"link": "upper_arm"}}, "min_seconds"),
    ({"stood_on": {"link": "upper_arm", "min_seconds": 1, "min_tilt": 200}}, "min_tilt"),
    ({"got_up": {"lay_seconds": 1.0}}, "within_seconds"),
])
def test_new_expectations_are_validated(entry, message):
    from puppet.data.errors import DataError
    from puppet.timeline.expectations import parse_expectations

    with pytest.raises(DataError, match=message):
        parse_expectations([entry])


def test_stood_on_and_got_up_name_what_they_measured():
    kip = replayed("luxo-kip")
    (out,) = check(kip, [{"stood_on": {"link": "base", "min_seconds": 0.5, "min_tilt": 80}}])
    assert "longest stretch on base alone" in out.measured
    (out,) = check(replayed("luxo-hop"), [{"got_up": {"lay_seconds": 1, "within_seconds": 1}}])
    assert out.measured.startswith("never lay")
