"""The gymnast on the floor (interfaces/biped-floor.yaml): the balanced_on expectation
and the floor feats' logs."""

from __future__ import annotations

import numpy as np
import pytest

from puppet.data.errors import DataError
from puppet.timeline.expectations import evaluate, parse_expectations


class _Run:
    """A tiny trajectory: links hand_a, hand_b, head, foot, sampled every 0.1 s."""

    links = ["hand_a", "hand_b", "head", "foot"]

    def __init__(self, degrees, contact, head_y, foot_y):
        n = len(degrees)
        self.t = np.arange(n) * 0.1
        self.root_angle = np.radians(np.asarray(degrees, dtype=float))
        self.contact = np.array(contact, dtype=bool)
        self.y = np.stack([np.zeros(n), np.zeros(n), head_y, foot_y], axis=1).astype(float)

    def index(self, link):
        return self.links.index(link)


def _outcome(item, traj):
    e, = parse_expectations([item]).items
    return evaluate(e, traj, "")


HANDS = {"links": ["hand_a", "hand_b"], "min_seconds": 0.3, "above": ["foot"], "over": "head"}
#                  up   tipping      upside down on the hands        feet down   a foot too
DEG = [0, 90, 180, 180, 180, 180, 180, 180]
CONTACT = [[0, 0, 0, 1], [1, 1, 0, 1], [1, 0, 0, 0], [1, 1, 0, 0], [0, 1, 0, 0],
           [1, 1, 0, 0], [1, 1, 0, 1], [1, 1, 0, 0]]
HEAD = [1.6, 1.0, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3]
FEET = [0.0, 0.5, 1.5, 1.5, 1.5, 0.2, 1.5, 1.5]


def test_balanced_on_measures_the_longest_stretch_on_those_links_alone_feet_up():
    got = _outcome({"balanced_on": HANDS}, _Run(DEG, CONTACT, HEAD, FEET))
    # samples 2-4: one hand or both, nothing else, upside down, the foot above the head;
    # sample 5 has the foot below the head, sample 6 the foot touching
    assert got.passed and got.measured == ("longest stretch on hand_a, hand_b alone, upside "
                                           "down: 0.300 s (t = 0.20 to 0.40 s)")
    longer = _outcome({"balanced_on": {**HANDS, "min_seconds": 0.4}},
                      _Run(DEG, CONTACT, HEAD, FEET))
    assert not longer.passed and longer.expectation.startswith("balanced_on hand_a, hand_b")


def test_balanced_on_fails_when_another_link_touches_or_the_root_is_not_upside_down():
    touching = [[1, 1, 1, 0]] * 8  # the head on the ground too: a headstand, not this
    got = _outcome({"balanced_on": HANDS}, _Run(DEG, touching, HEAD, FEET))
    assert not got.passed and got.measured.endswith("0.000 s")
    upright = _outcome({"balanced_on": HANDS}, _Run([0] * 8, CONTACT, HEAD, FEET))
    assert not upright.passed


def test_balanced_on_names_a_misspelt_link_and_wants_above_with_over():
    with pytest.raises(DataError, match="unknown link 'toe'"):
        _outcome({"balanced_on": {**HANDS, "above": ["toe"]}}, _Run(DEG, CONTACT, HEAD, FEET))
    with pytest.raises(DataError, match="'above'.*'over'"):
        parse_expectations([{"balanced_on": {"links": ["hand_a"], "min_seconds": 1,
                                             "above": ["foot"]}}])


# -- the logs ---------------------------------------------------------------------------
import json  # noqa: E402
import shutil  # noqa: E402
from pathlib import Path  # noqa: E402

import yaml  # noqa: E402

from puppet.data.catalog import ROOT, find  # noqa: E402
from puppet.testing import replay_log  # noqa: E402

LOGS = ROOT / "assets" / "logs"


def _variant(name: str, tmp_path: Path, edit=None, friction: float = 1.0) -> set[str]:
    """The log replayed against a copy of its interface changed by ``edit`` (and its
    scene's friction times ``friction``); the kinds of the expectations that fail."""
    log = LOGS / f"{name}.jsonl"
    lines = log.read_text(encoding="utf-8").splitlines(keepends=True)
    head = json.loads(lines[0])
    iface = yaml.safe_load(find("interface", head["interface"]).read_text(encoding="utf-8"))
    if edit is not None:
        edit(iface)
    iface["name"] += "-variant"
    scene = yaml.safe_load(find("scene", head["scene"]).read_text(encoding="utf-8"))
    for g in scene["ground"]:
        g["friction"] = g.get("friction", 0.8) * friction
    scene["name"] += "-variant"
    (tmp_path / "scene-variant.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    iface["scene"] = str(tmp_path / "scene-variant.yaml")
    ipath = tmp_path / "iface-variant.yaml"
    ipath.write_text(yaml.safe_dump(iface), encoding="utf-8")
    head.update(interface=str(ipath), interface_text=ipath.read_text(encoding="utf-8"),
                scene=str(tmp_path / "scene-variant.yaml"))
    out = tmp_path / log.name
    out.write_text(json.dumps(head) + "\n" + "".join(lines[1:]), encoding="utf-8")
    shutil.copy(LOGS / f"{name}.expect.yaml", tmp_path / f"{name}.expect.yaml")
    return {o.expectation.split()[0].rstrip(":") for o in replay_log(out).failed} - {"same"}


def _character_shoulders(iface: dict) -> None:
    """The character's own (a standing figure's) shoulders and elbows."""
    for j in ("shoulder_near", "shoulder_far", "elbow_near", "elbow_far"):
        iface["gains"].pop(j)


def test_handstand_log_holds_on_the_hands_alone_feet_up():
    result = replay_log(LOGS / "biped-handstand.jsonl")
    assert not result.failed, [str(o) for o in result.failed]


def test_handstand_fails_with_the_characters_own_arms(tmp_path):
    assert "balanced_on" in _variant("biped-handstand", tmp_path, _character_shoulders)


def test_handstand_fails_without_its_balance_maps(tmp_path):
    """The handstand state's sensor maps gone (the pose and the straight elbows alone):
    the figure topples off its hands, so the balance is the feedback, not a lucky pose."""
    def no_balance(iface):
        maps = iface["states"]["handstand"]["maps"]
        iface["states"]["handstand"]["maps"] = [m for m in maps if "input" not in m]

    assert "balanced_on" in _variant("biped-handstand", tmp_path, no_balance)


def test_handstand_fails_on_a_slippery_floor(tmp_path):
    assert "balanced_on" in _variant("biped-handstand", tmp_path, friction=0.3)


def test_handstand_fails_when_the_press_does_not_hand_over_to_it(tmp_path):
    """The press state's sensor transition gone (only a late timer left): the press
    alone stays piked, so h's handstand is the state machine's doing."""
    def no_handover(iface):
        iface["states"]["hs_press"]["transitions"] = [{"to": "hs_kick", "after": 30.0}]

    assert "balanced_on" in _variant("biped-handstand", tmp_path, no_handover)


def test_handstand_is_on_straight_arms_with_the_head_clear_of_the_floor():
    """While it balances (the pelvis at least 150 deg from upright), the elbows stay
    within 15 deg of straight and the head's lowest point 0.15 m or more above the floor:
    a handstand, not a bent-arm or forearm stand."""
    result = replay_log(LOGS / "biped-handstand.jsonl")
    tr = result.trajectory
    up = np.abs(np.degrees(np.remainder(tr.root_angle + np.pi, 2 * np.pi) - np.pi)) >= 150
    assert up.sum() * (tr.t[1] - tr.t[0]) > 2.0
    for elbow in ("elbow_near", "elbow_far"):
        bend = np.degrees(tr.joint_angle[up, tr.joints.index(elbow)])
        assert bend.max() < 15, (elbow, bend.max())
    assert tr.lowest[up, tr.index("head")].min() > 0.15


def test_bound_mode_drives_hips_knees_shoulders_and_elbows_together():
    """Key 2 (bound) and the mouse up: the targets of both hips, knees, shoulders and
    elbows go to the gathered end together; key 1 lets the mouse go again."""
    import math

    from puppet.data.catalog import load_setup
    from puppet.session import Session
    from puppet.session.playback import play
    from puppet.timeline.script import ScriptSpec, compile_script

    session = Session(load_setup("biped-floor"))
    spec = ScriptSpec.model_validate({"events": [
        {"t": 0.0, "mouse": [0.5, 0.5]}, {"t": 0.1, "key": "2"},
        {"t": 0.2, "mouse": [0.5, 1.0], "over": 0.1}, {"t": 0.5, "key": "1"},
        {"t": 0.6, "mouse": [0.5, 0.0], "over": 0.1}]})
    events = compile_script(spec, session.sim.dt)
    servos = session.character.servos

    def targets():
        return {n: round(math.degrees(servos[n].target)) for n in (
            "hip_near", "hip_far", "knee_near", "knee_far", "shoulder_near",
            "shoulder_far", "elbow_near", "elbow_far")}

    half = round(0.45 / session.sim.dt)
    play(session, [e for e in events if e[0] <= half], half)
    assert session.runtime.mode == "bound"
    assert targets() == {"hip_near": 110, "hip_far": 110, "knee_near": -120, "knee_far": -120,
                         "shoulder_near": 90, "shoulder_far": 90, "elbow_near": 90,
                         "elbow_far": 90}
    play(session, [e for e in events if e[0] > half], round(0.8 / session.sim.dt))
    assert session.runtime.mode == "keys" and targets()["hip_near"] == 110  # let go


def test_f_back_flips_in_the_air_and_lands_on_the_feet(tmp_path):
    """Key f of biped-floor at 0.5 s (the log biped-backflip now plays the sensor-phased
    flip of interfaces/biped-backflip.yaml; this is the floor layout's own): the figure
    turns at least 300 deg backward with nothing touching, and the first links down
    after that flight are the feet. With the character's own leg damping in the
    take-off (50 and 30 N*m*s/rad) the legs cannot straighten fast enough to fly."""
    from puppet.data.catalog import load_setup, setup_from_text
    from puppet.session import Session
    from puppet.session.playback import play
    from puppet.timeline.script import compile_script, load_script, run_seconds
    from puppet.timeline.trajectory import Sampler, sample_every

    def flip(text=None):
        setup = load_setup("biped-floor") if text is None else setup_from_text(
            text, str(find("interface", "biped-floor")), None, None)
        session = Session(setup)
        script = tmp_path / "floor-flip.yaml"
        script.write_text("interface: biped-floor\nscene: biped-track\nseconds: 8.0\n"
                          "events:\n  - {t: 0.5, key: f}\n", encoding="utf-8")
        spec = load_script(script)
        sampler = Sampler(session)
        sampler(session)
        play(session, compile_script(spec, session.sim.dt),
             round(run_seconds(spec) / session.sim.dt), sample_every(session.sim.dt),
             sampler)
        return sampler.trajectory()

    def turned(tr):
        e, = parse_expectations([{"turned": {"link": "pelvis", "min_degrees": 300,
                                             "in_flight": True}}]).items
        return evaluate(e, tr, "")

    tr = flip()
    assert turned(tr).passed, turned(tr).measured
    from puppet.timeline.expectations.measure import longest_run as _longest_run

    length, _, last = _longest_run(~tr.contact.any(axis=1), tr.t)
    assert length > 0.3, length
    down = {tr.links[k] for k in np.flatnonzero(tr.contact[last + 1])}
    assert down and down <= {"foot_near", "foot_far"}, down
    iface = yaml.safe_load(find("interface", "biped-floor").read_text(encoding="utf-8"))
    del iface["poses"]["flip_jump"]["damping"]
    assert not turned(flip(yaml.safe_dump(iface))).passed


# -- touched: a foot on the wall ---------------------------------------------------------
class _Feet:
    """Links foot and hand sampled every 0.1 s: contact, lowest point and x given."""

    links = ["foot", "hand"]

    def __init__(self, contact, lowest, x):
        self.t = np.arange(len(contact)) * 0.1
        self.contact = np.array(contact, dtype=bool)
        self.lowest = np.array(lowest, dtype=float)
        self.x = np.array(x, dtype=float)

    def index(self, link):
        return self.links.index(link)


#            on the floor  foot on the wall  in the air   hand up high, in the air   down
WALL_C = [[1, 0], [1, 0], [1, 0], [0, 0], [0, 0], [0, 0], [0, 0], [1, 0]]
WALL_LOW = [[0, 1], [0.4, 1], [0.5, 1], [1, 1], [1, 1.2], [1, 1], [1, 1], [0, 1]]
WALL_X = [[0, 0], [0.55, 0], [0.55, 0], [0.3, 0], [0.1, 0], [0, 0], [-0.3, 0], [-0.6, 0]]


def test_touched_finds_a_foot_up_on_the_wall_before_the_flight():
    got = _outcome({"touched": {"links": ["foot"], "min_height": 0.3, "min_x": 0.5,
                                "before_flight": True}}, _Feet(WALL_C, WALL_LOW, WALL_X))
    assert got.passed and got.measured == ("foot touched at t = 0.10 s, lowest point "
                                           "0.400 m up, x = 0.550 m")
    higher = _outcome({"touched": {"links": ["foot"], "min_height": 0.6}},
                      _Feet(WALL_C, WALL_LOW, WALL_X))
    assert not higher.passed and higher.measured.endswith("(highest touch 0.500 m up)")
    further = _outcome({"touched": {"links": ["foot"], "min_height": 0.3, "min_x": 0.6}},
                       _Feet(WALL_C, WALL_LOW, WALL_X))
    assert not further.passed
    # the hand never touches; the foot's touch after the flight (on the floor) is low
    assert not _outcome({"touched": {"links": ["hand"], "min_height": 0.0}},
                        _Feet(WALL_C, WALL_LOW, WALL_X)).passed


def test_took_off_min_height_tells_a_take_off_from_the_wall_from_one_off_the_floor():
    """The flight began from the foot 0.5 m up the wall (sample 2); the same flight
    begun from the foot back on the floor below it (lowest point 0) fails min_height."""
    item = {"links": ["foot"], "min_height": 0.2}
    got = _outcome({"took_off": item}, _Feet(WALL_C, WALL_LOW, WALL_X))
    assert got.passed and got.measured.endswith("foot at x = 0.550 (lowest point 0.500 m up)")
    assert abs(got.margin - 0.3) < 1e-9
    floor = [row[:] for row in WALL_LOW]
    floor[2] = [0.0, 1]  # the foot slid down the wall to the floor before the flight
    low = _outcome({"took_off": item}, _Feet(WALL_C, floor, WALL_X))
    assert not low.passed and abs(low.margin + 0.2) < 1e-9
    assert _outcome({"took_off": {"links": ["foot"]}}, _Feet(WALL_C, floor, WALL_X)).passed


def test_touched_before_flight_ignores_a_touch_after_the_longest_flight():
    late = [[1, 0], [1, 0], [0, 0], [0, 0], [0, 0], [1, 0], [1, 0], [1, 0]]
    low = [[0, 1], [0, 1], [1, 1], [1, 1], [1, 1], [0.5, 1], [0.5, 1], [0, 1]]
    item = {"links": ["foot"], "min_height": 0.3}
    assert _outcome({"touched": item}, _Feet(late, low, WALL_X)).passed
    got = _outcome({"touched": {**item, "before_flight": True}}, _Feet(late, low, WALL_X))
    assert not got.passed and got.measured == "never touched that high (highest touch 0.000 m up)"


# -- the back flips ----------------------------------------------------------------------
def _weak_legs(iface: dict) -> None:
    """Hips and knees at 150 N*m instead of 250 (a weaker figure's legs), the poses' own
    caps (a take-off's) too."""
    legs = ("hip_near", "hip_far", "knee_near", "knee_far")
    for j in legs:
        iface["gains"][j] = {"stiffness": 1000, "damping": 50, "max_torque": 150}
    for pose in iface["poses"].values():
        for j in legs:
            if j in pose.get("max_torque", {}):
                pose["max_torque"][j] = 150


def _moved_key(name: str):
    """The key ``name`` re-bound to j, at the top level and in every state's keys."""
    def edit(iface: dict) -> None:
        lists = [iface.get("keys", [])]
        lists += [st.get("keys", []) for st in (iface.get("states") or {}).values()]
        for keys in lists:
            for k in keys:
                if k["key"] == name:
                    k["key"] = "j"
    return edit


def test_backflip_log_turns_in_the_air_lands_on_the_feet_and_stands():
    result = replay_log(LOGS / "biped-backflip.jsonl")
    assert not result.failed, [str(o) for o in result.failed]


def test_backflip_fails_with_weak_legs(tmp_path):
    """Hips and knees capped at 150 N*m (the push pose's caps too): the sensor-phased flip
    still turns over in the air, but the weaker take-off and landing put it down where
    it cannot stand, and it falls."""
    assert {"never_fell", "height_at_end"} <= _variant("biped-backflip", tmp_path, _weak_legs)


def test_backflip_fails_on_a_slippery_floor(tmp_path):
    assert {"never_fell", "height_at_end"} & _variant("biped-backflip", tmp_path, friction=0.3)


def test_backflip_fails_without_the_landing_state(tmp_path):
    """The state entered at the touch-down does nothing (no crouch, no ankle maps, no
    stand-up after it within the run): the figure stays in the landing pose."""
    def no_landing(iface):
        iface["states"]["flip_landed"] = {"transitions": [{"to": "flip_rise", "after": 30.0}]}

    assert "height_at_end" in _variant("biped-backflip", tmp_path, no_landing)


def test_backflip_fails_when_f_is_moved(tmp_path):
    assert "turned" in _variant("biped-backflip", tmp_path, _moved_key("f"))


def test_wall_flip_log_pushes_off_the_wall_turns_and_lands_on_the_feet():
    result = replay_log(LOGS / "biped-wall-flip.jsonl")
    assert not result.failed, [str(o) for o in result.failed]


def test_wall_flip_fails_with_weak_legs(tmp_path):
    """Hips and knees capped at 150 N*m: the push off the wall does not turn it over."""
    assert "turned" in _variant("biped-wall-flip", tmp_path, _weak_legs)


def test_wall_flip_fails_on_a_slippery_wall(tmp_path):
    """At 0.3 of the friction (the wall's and the floor's) the push does not turn it over."""
    assert "turned" in _variant("biped-wall-flip", tmp_path, friction=0.3)


def test_wall_flip_fails_when_w_is_moved(tmp_path):
    assert "touched" in _variant("biped-wall-flip", tmp_path, _moved_key("w"))


def test_touched_before_flight_fails_when_there_is_no_flight():
    grounded = [[1, 0]] * 8  # the foot high on the wall, but never a flight
    high = [[0.5, 1]] * 8
    item = {"links": ["foot"], "min_height": 0.3}
    assert _outcome({"touched": item}, _Feet(grounded, high, WALL_X)).passed
    got = _outcome({"touched": {**item, "before_flight": True}}, _Feet(grounded, high, WALL_X))
    assert not got.passed and got.measured.startswith("no flight")
