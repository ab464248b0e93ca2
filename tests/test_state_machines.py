"""Several state machines side by side, any_state rules, a state that goes to itself,
sequences that repeat, and the load-time errors of these features (file:line:col).

Played through Session.handle/advance, as the window does."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import load_setup, setup_from_text
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session

BROKEN = Path(__file__).parent / "broken"

MACHINES = """
name: t
description: two machines side by side
character: luxo
poses:
  stand: {joints: {ankle: -25, knee: 55}}
  fold: {joints: {knee: 110}}
keys:
  - {key: k, pose: fold}
  - {key: "1", pose: stand}
states:                      # the machine 'main': a metronome on the ankle
  waiting:
    transitions: [{to: ticking, after: 0.5}]
  ticking:
    enter: {adjust: {ankle: -2}}
    keys:
      - {key: a, goto: ticking}    # to itself: the entry runs again, the clock restarts
    transitions: [{to: waiting, after: 0.5}]
machines:
  watch:                     # watches the knee, whatever main does
    states:
      open:
        enter: {stiffness: {ankle: 18}}
      folded:
        enter: {stiffness: {ankle: 25}}
    any_state:
      transitions:
        - {to: folded, when: {sensor: joint.knee, above: 100}}
        - {to: open, after: 1.5}
"""


def session(tmp_path, text: str) -> Session:
    path = tmp_path / "t.yaml"
    path.write_text(textwrap.dedent(text))
    return Session(load_setup(str(path)))


def press(s, key):
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


def timeline(s, steps: int, every: int = 8) -> list[tuple[int, dict]]:
    out = []
    for _ in range(steps // every):
        s.advance(every)
        out.append((s.steps, dict(s.runtime.states)))
    return out


def test_two_machines_run_side_by_side_with_an_any_state_sensor_and_timer(tmp_path):
    quiet = session(tmp_path, MACHINES)
    assert quiet.runtime.states == {"main": "waiting", "watch": "open"}
    assert quiet.character.servos["ankle"].stiffness == 18  # open's entry ran at the start
    calm = timeline(quiet, 1200)

    s = session(tmp_path, MACHINES)
    s.advance(104)
    press(s, "k")  # fold the knee: watch sees it, main goes on as before
    busy = timeline(s, 1096)
    assert [(t, st["main"]) for t, st in busy] == [(t, st["main"]) for t, st in calm[13:]]
    folded = [t for t, st in busy if st["watch"] == "folded"]
    assert folded and folded[0] - 104 < 0.4 * 480  # the knee passes 100 deg soon
    assert s.character.servos["ankle"].stiffness == 25
    # any_state's timer leads back to open after 1.5 s in folded - and since the knee is
    # still folded, its sensor rule takes it straight back to folded (a timer leading
    # out of a state and a sensor leading in: both any_state's), in the same step
    again = s.runtime.machines["watch"].entered  # entered folded anew, 1.5 s after the first
    assert folded[0] - 8 <= again - 720 < folded[0]  # (sampled every 8 steps)
    assert s.runtime.states["watch"] == "folded"
    press(s, "1")  # stand: the knee unfolds
    s.advance(int(1.6 * 480))
    assert s.runtime.states["watch"] == "open"
    assert s.character.servos["ankle"].stiffness == 18
    # main ticked every second: waiting 0.5 s, ticking (ankle -2 deg) 0.5 s
    ticks = sum(1 for (_, a), (_, b) in zip(calm, calm[1:])
                if a["main"] == "waiting" and b["main"] == "ticking")
    assert ticks == 2


def test_a_goto_to_the_current_state_runs_its_entry_again_and_restarts_its_clock(tmp_path):
    s = session(tmp_path, MACHINES)
    s.advance(241)  # into ticking at step 240: its entry turned the ankle 2 deg
    assert s.runtime.states["main"] == "ticking"
    ankle = math.degrees(s.character.servos["ankle"].target)
    assert ankle == pytest.approx(-27)
    s.advance(100)
    press(s, "a")
    assert math.degrees(s.character.servos["ankle"].target) == pytest.approx(-29)
    assert s.runtime.machines["main"].entered == 341
    s.advance(200)  # 0.5 s after the first entry: still ticking (the clock restarted)
    assert s.runtime.states["main"] == "ticking"
    s.advance(41)  # 0.5 s after the goto
    assert s.runtime.states["main"] == "waiting"


SEQUENCES = """
name: t
description: repeated sequences
character: luxo
poses:
  bend: {joints: {ankle: -30, knee: 65}}
  stand: {joints: {ankle: -25, knee: 55}}
sequences:
  nod: [{pose: bend, hold: 0.1}, {pose: stand, hold: 0.1}]
keys:
  - {key: n, sequence: nod, repeat: 3}
  - {key: m, sequence: nod, repeat: forever}
  - {key: "1", pose: stand}
"""


def knee_changes(s, steps: int) -> tuple[list[int], list]:
    """Steps at which the knee's target changed, and the sequence after each step."""
    changes, running = [], []
    last = s.character.servos["knee"].target
    for _ in range(steps):
        s.advance(1)
        now = s.character.servos["knee"].target
        if now != last:
            changes.append(s.steps - 1)  # the tick before stepping from there wrote it
            last = now
        running.append(s.runtime.sequence)
    return changes, running


def test_a_sequence_with_repeat_3_plays_three_times_then_ends(tmp_path):
    s = session(tmp_path, SEQUENCES)
    s.advance(10)
    press(s, "n")  # bend at once, then stand, bend, stand, bend, stand (0.1 s each)
    changes, running = knee_changes(s, 400)
    assert changes == [10 + 48 * i for i in range(1, 6)]
    ended = running.index(None)
    assert ended == 6 * 48  # the tick at step 10 + 288 ends it (while stepping from there)
    assert all(r is None for r in running[ended:])
    assert s.runtime.next_wakeup is None


def test_a_sequence_repeated_forever_runs_until_preempted(tmp_path):
    s = session(tmp_path, SEQUENCES)
    press(s, "m")
    changes, _ = knee_changes(s, 10 * 96)  # ten plays
    assert changes == [48 * i for i in range(1, 20)]
    assert s.runtime.sequence is not None and s.runtime.sequence.plays_left is None
    press(s, "1")  # a pose takes both its joints: it ends
    s.advance(48)
    assert s.runtime.sequence is None and s.runtime.next_wakeup is None
    press(s, "m")
    press(s, "n")  # a new sequence replaces it: three plays, then idle
    s.advance(6 * 48 + 1)
    assert s.runtime.sequence is None


# -- load-time errors -----------------------------------------------------------------------
@pytest.mark.parametrize("name, where", [
    ("iface-goto-unknown-machine-state", (12, 28)),
    ("iface-goto-ambiguous-state", (8, 20)),
    ("iface-machine-named-main", (8, 3)),
    ("iface-machine-unreachable-state", (14, 7)),
    ("iface-reach-unknown-prop", (9, 50)),
    ("iface-reach-target-and-steer", (10, 7)),
    ("iface-transition-other-machine", (9, 14)),
])
def test_errors_of_the_new_features_name_file_line_and_column(name, where):
    """The broken files are also in test_loader's list; here: the column too."""
    path = BROKEN / f"{name}.yaml"
    with pytest.raises(DataError) as info:
        check_file(path)
    assert (info.value.line, info.value.col) == where, str(info.value)
    assert str(info.value).startswith(f"{path}:{where[0]}:{where[1]}: ")


def test_play_refuses_a_reach_for_a_prop_of_another_scene(tmp_path):
    """The prop is checked against the scene actually played (``--scene``), too."""
    text = (BROKEN / "iface-reach-unknown-prop.yaml").read_text().replace("rial", "rail")
    setup_from_text(text, "x.yaml")  # the pendulum scene has a rail
    with pytest.raises(DataError) as info:
        setup_from_text(text, "x.yaml", scene="flat")
    assert str(info.value).startswith("x.yaml:9:50: unknown prop 'rail' in scene 'flat'")


EVERYTHING = """
name: t
description: every controller at once, on the cat
character: cat
scene: cat-flat
poses:
  back_a: {joints: {hip_near: 30, hip_far: 14}}
  back_b: {joints: {hip_near: 20, hip_far: 24}}
sequences:
  shuffle: [{pose: back_a, hold: 0.15}, {pose: back_b, hold: 0.15}]
chains:
  paw: {joints: [shoulder_near, elbow_near], end: [0.10, 0.012]}
perturbation: {impulse: 0.0005, every: 0.05, seed: 9}
keys:
  - {key: q, sequence: shuffle, repeat: forever}
  - key: w
    reach: {chain: paw, steer: {x: channel.px, y: channel.py, x_to: [0.12, 0.2],
            y_to: [0.02, 0.08]}, duration: 0.3}
  - {key: g, grasp: {chain: paw, points: [[5.0, 5.0]], tolerance: 0.03}}
  - {key: t, perturb: "on"}
states:
  one:
    enter: {adjust: {neck: 5}}
    transitions: [{to: two, after: 0.35}]
  two:
    enter: {adjust: {neck: -5}}
    transitions: [{to: one, after: 0.4}]
machines:
  tail:
    states:
      low:
        enter: {set: {tail: 10}}
      high:
        enter: {set: {tail: 40}}
    any_state:
      transitions:
        - {to: high, when: {sensor: joint.hip_near, above: 27}}
        - {to: low, when: {sensor: joint.hip_near, below: 23}}
"""


def test_every_controller_running_at_once_comes_back_exactly_from_a_checkpoint(tmp_path):
    from puppet.session.playback import play

    events = [(10, ev.key("q")), (20, ev.key("w")), (30, ev.key("g")), (40, ev.key("t"))]
    events += [(50 + 16 * i, ev.channels({"px": (i % 7) / 6, "py": (i % 5) / 4}))
               for i in range(60)]
    events = sorted(events + [(500, ev.key("c"))], key=lambda e: e[0])  # a checkpoint
    straight = session(tmp_path, EVERYTHING)
    seen = set()
    play(straight, events, 1500, 8, lambda s: seen.add(tuple(s.runtime.states.values())))
    assert seen == {("one", "low"), ("one", "high"), ("two", "low"), ("two", "high")}
    r = straight.runtime
    assert r.sequence is not None and "paw" in r.reaches and "paw" in r.grasping.armed
    assert r.perturber.on
    want = straight.sim.state_hash()

    s = session(tmp_path, EVERYTHING)
    play(s, events, 1200)
    s.handle(ev.action("restore"))
    assert s.steps == 500
    play(s, [e for e in events if e[0] > 500], 1500)
    assert s.sim.state_hash() == want
    assert s.runtime.get_state() == straight.runtime.get_state()


MOUSE_GEARS = """
name: t
description: the mouse's x as a transition sensor
character: luxo
control_rate: 120
poses:
  low: {joints: {knee: 40}}
  high: {joints: {knee: 90}}
states:
  slow:
    enter: {pose: low}
    transitions:
      - {to: fast, when: {sensor: input.mouse.x, above: 0.7}}
  fast:
    enter: {pose: high}
    transitions:
      - {to: slow, when: {sensor: input.mouse.x, below: 0.6}}
"""


def test_a_state_changes_on_a_device_input_and_not_before_it_has_a_value(tmp_path):
    """input.mouse.x is the mouse's x (0..1) as a sensor: no condition on it holds
    until the mouse has moved (a below: 0.6 would otherwise fire at once), then the
    state follows it both ways, with the gap between 0.6 and 0.7 as hysteresis."""
    s = session(tmp_path, MOUSE_GEARS.replace("to: fast, when: {sensor: input.mouse.x, "
                                              "above: 0.7}",
                                              "to: fast, when: {sensor: input.mouse.x, "
                                              "below: 0.6}"))
    s.advance(60)
    assert s.runtime.states["main"] == "slow"  # NaN: below 0.6 does not hold yet
    s = session(tmp_path, MOUSE_GEARS)
    seen = []
    for x in (0.5, 0.65, 0.75, 0.65, 0.55, 0.8):
        s.handle(ev.mouse(x, 0.5))
        s.advance(8)
        seen.append(s.runtime.states["main"])
    assert seen == ["slow", "slow", "fast", "fast", "slow", "fast"]
    assert s.character.servos["knee"].target == pytest.approx(math.radians(90))


@pytest.mark.parametrize("sensor, message", [
    ("input.mouse.z", "unknown input 'mouse.z'"),
    ("input.sensor.com.vx", "is not a device input"),
])
def test_a_bad_device_input_sensor_is_a_one_line_error(tmp_path, sensor, message):
    path = tmp_path / "t.yaml"
    path.write_text(textwrap.dedent(MOUSE_GEARS).replace("input.mouse.x, above",
                                                         f"{sensor}, above"))
    with pytest.raises(DataError, match=message) as info:
        check_file(path)
    assert str(info.value).startswith(f"{path}:13:35: ") and "\n" not in str(info.value)


def test_a_pose_caps_a_servos_torque_until_another_pose_does(tmp_path):
    """A pose's max_torque, like its stiffness, is the servo's from then on: Luxo's
    knee capped at 0.05 N*m gives no more than that and gives way under the arm's
    weight, where the uncapped knee holds its angle; the next pose lifts the cap."""
    text = """
name: t
description: a pose's torque cap
character: luxo
poses:
  weak: {joints: {knee: 55}, max_torque: {knee: 0.05}}
  strong: {joints: {knee: 55}, max_torque: {knee: 40}}
keys:
  - {key: w, pose: weak}
  - {key: s, pose: strong}
"""
    moved = {}
    for key in ("w", "s"):
        s = session(tmp_path, text)
        s.advance(240)
        knee = s.character.servos["knee"]
        before = knee.angle
        press(s, key)
        torques = []
        for _ in range(120):
            s.advance(1)
            torques.append(abs(knee.torque(s.sim.dt)))
        moved[key] = abs(knee.angle - before)
        if key == "w":
            assert knee.max_torque == 0.05 and max(torques) <= 0.05 + 1e-9
            press(s, "s")
            assert knee.max_torque == 40
    assert moved["w"] > math.radians(10) and moved["s"] < moved["w"] / 10, moved


ALL_OF = """
name: t
description: a transition on two conditions at once
character: luxo
poses:
  fold: {joints: {knee: 120}}
keys:
  - {key: k, pose: fold}
states:
  idle:
    transitions:
      - to: both
        when: [{sensor: joint.knee, above: 100}, {sensor: contact.base, is: true}]
  both: {}
"""


def test_a_transition_with_a_list_of_conditions_fires_only_when_all_hold(tmp_path):
    s = session(tmp_path, ALL_OF)
    s.advance(480)  # standing: the base is down but the knee is at 55
    assert s.runtime.state == "idle"
    press(s, "k")  # the knee folds past 100 with the base still down: both hold
    for _ in range(240):
        s.advance(1)
        if s.runtime.state == "both":
            break
    knee = math.degrees(s.character.bodies["upper_arm"].angle
                        - s.character.bodies["lower_arm"].angle)
    assert s.runtime.state == "both" and knee > 100
    assert s.character.in_contact("base")


def test_a_list_of_conditions_fails_while_one_of_them_does(tmp_path):
    text = ALL_OF.replace("{sensor: contact.base, is: true}", "{sensor: contact.base, is: false}")
    s = session(tmp_path, text)
    press(s, "k")
    s.advance(480)  # the knee is folded but the base never leaves the floor
    assert s.runtime.state == "idle"
