"""Behaviours the third fresh seeded mutation run of issue 17 (seed 31) found no test
looking at, each tested as the feature reads: the centre of mass's offset from a link,
grasps carried over a hot reload, an unsent steering input, sensor maps that set a
target, a ghost of the session as played, log messages
and lines, a BVH hierarchy's offsets and box-ended leaves, the scrub preview after a
branch, the viewer's replay of app actions, the replay command's default, a scripted
key's release."""

from __future__ import annotations

import json
import math
import shutil
import textwrap
from pathlib import Path

import numpy as np
import pytest

from puppet.data.catalog import load_setup
from puppet.data.characters import load_character
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.interface.conditions import reader
from puppet.session import Session
from puppet.timeline.log import read_log, record_events

ROOT = Path(__file__).resolve().parents[1]
LOGS = ROOT / "assets" / "logs"


def make(tmp_path, text: str, name: str = "iface.yaml") -> Session:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return Session(load_setup(str(path)))


def tap(s: Session, key: str) -> None:
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


# -- sensors ---------------------------------------------------------------------------------
def test_com_dx_of_a_link_is_the_horizontal_offset_from_that_links_centre():
    """``com.dx.head`` on a figure leaning forward: the head is ahead of the centre of
    mass by a few centimetres, and well below it in height - the sensor reads x only."""
    s = Session(load_setup("biped-stand"))
    s.advance(120)
    c = s.character
    for link in ("head", "foot_near", "pelvis"):
        got = reader(f"com.dx.{link}", c)()
        want = c.com()[0] - c.link_position(link)[0]
        assert got == pytest.approx(want, abs=1e-12), link
    # the head is 1.6 m up: a reading mixing in y would be off by metres
    assert abs(reader("com.dx.head", c)()) < 0.2


def test_a_sensor_map_that_sets_a_target_follows_its_sensor(tmp_path):
    s = make(tmp_path, """
    name: t
    description: the near shoulder's target follows the pelvis angle (a set map, not add)
    character: biped
    maps:
      - {input: sensor.angle.pelvis, joint: shoulder_near, from: [-0.5, 0.5], to: [-50, 50]}
    """)
    for shove in (None, [8.0, 0.0]):  # standing, then pushed forward
        if shove:
            s.handle(ev.push("chest", shove))
        s.advance(240)
        angle = reader("angle.pelvis", s.character)()
        want = max(-50.0, min(50.0, -50.0 + 100.0 * (angle + 0.5)))
        got = math.degrees(s.character.servos["shoulder_near"].target)
        assert got == pytest.approx(want, abs=2.0)  # read at the control rate, a step back


# -- reaches and grasps ----------------------------------------------------------------------
LUXO = """
name: t
description: reaches and grasps in the pendulum scene
character: luxo
scene: pendulum
gains:
  ankle: {stiffness: 60, damping: 0.6, max_torque: 40}
  knee: {stiffness: 40, damping: 0.4, max_torque: 30}
chains:
  shade: {joints: [ankle, knee], end: [0.0, 0.43]}
keys:
  - key: s
    reach: {chain: shade, steer: {x: channel.hx, y: channel.hy, x_to: [-0.04, 0.06],
            y_to: [0.32, 0.40]}, duration: 0.3}
  - {key: g, reach: {chain: shade, point: {prop: rail}, duration: 0.4, hold: 0.4,
                     grasp: true, tolerance: 0.03}}
  - {key: u, release: all}
"""


def test_a_steering_input_not_sent_yet_counts_as_the_middle_of_its_range(tmp_path):
    s = make(tmp_path, LUXO)
    s.advance(120)
    s.handle(ev.channels({"hx": 1.0}))  # hy never sent
    tap(s, "s")
    s.advance(2)
    x, y = s.runtime.reaching.target_now(s.runtime.reaches["shade"].target)
    base = s.character.bodies["base"]
    want = base.local_to_world((0.06, 0.36))  # x at its top, y in the middle of [0.32, 0.40]
    assert math.dist((x, y), want) < 1e-9


def test_a_grasp_held_over_a_hot_reload_stays_held_unless_its_chain_changed(tmp_path):
    s = make(tmp_path, LUXO)
    s.advance(120)
    tap(s, "g")
    s.advance(600)
    assert "shade" in s.runtime.grasped
    held = s.runtime.grasped["shade"]
    s.reload(textwrap.dedent(LUXO).replace("description: reaches", "description: Reaches"),
             str(tmp_path / "iface.yaml"))
    s.advance(60)
    assert s.runtime.grasped.get("shade") == held  # the same chain: it holds on
    s.reload(textwrap.dedent(LUXO).replace("end: [0.0, 0.43]", "end: [0.0, 0.42]"),
             str(tmp_path / "iface.yaml"))
    s.advance(2)
    assert "shade" not in s.runtime.grasped  # the chain changed: it let go


# -- the ghost and the replay command --------------------------------------------------------
IFACE = """
name: t
description: the ankle on the mouse
character: luxo
maps:
  - {input: mouse.x, joint: ankle, from: [0, 1], to: [60, -60]}
"""


def _recorded(tmp_path) -> tuple[Path, Path]:
    iface = tmp_path / "t.yaml"
    iface.write_text(textwrap.dedent(IFACE))
    log = tmp_path / "t.jsonl"
    s = Session(load_setup(str(iface)))
    record_events(s, [(0, ev.mouse(1.0, 0.5)), (240, ev.mouse(0.0, 0.5))], 480, log)
    iface.write_text(textwrap.dedent(IFACE).replace("to: [60, -60]", "to: [10, -10]"))
    return iface, log


def test_a_ghost_plays_the_session_as_played_not_todays_interface(tmp_path):
    from puppet.timeline.ghost import Ghost

    _, log = _recorded(tmp_path)
    ghost = Ghost(log)
    assert ghost.setup.interface.maps[0].to == (60, -60)  # the recorded copy
    live = Session(load_setup("luxo-mouse"))
    live.advance(480)
    ghost.sync(live)
    assert ghost.session.sim.state_hash() == read_log(log).end_hash


def test_the_replay_command_replays_todays_interface_unless_asked_for_the_recorded(tmp_path):
    from puppet.timeline.report import replay_one

    _, log = _recorded(tmp_path)
    today = replay_one(str(log), None, False, False)
    recorded = replay_one(str(log), None, False, False, as_recorded=True)
    assert today["same_end"] is False and any("differs from the one recorded" in w
                                            for w in today["warnings"])
    assert recorded["same_end"] is True


# -- log lines -------------------------------------------------------------------------------
def _log_with(tmp_path, edit) -> Path:
    lines = (LOGS / "luxo-hop.jsonl").read_text().splitlines()
    lines = edit(lines)
    out = tmp_path / "edited.jsonl"
    out.write_text("\n".join(lines) + "\n")
    return out


def test_an_unknown_action_in_a_log_lists_every_action_a_log_may_hold(tmp_path):
    path = _log_with(tmp_path, lambda ls: ls[:2] + [
        '{"step":10,"event":{"type":"action","name":"frobnicate"}}'] + ls[2:])
    with pytest.raises(DataError) as info:
        read_log(path)
    msg = str(info.value)
    assert msg.startswith(f"{path}:3:") and "unknown action 'frobnicate'" in msg
    listed = msg.split("expected one of: ")[1].split(" (")[0].split(", ")
    assert "rewind" in listed and "take" in listed and "checkpoint" in listed


def test_a_log_of_another_format_version_names_the_file(tmp_path):
    def bump(ls):
        h = json.loads(ls[0])
        h["version"] = 99
        return [json.dumps(h)] + ls[1:]
    path = _log_with(tmp_path, bump)
    with pytest.raises(DataError) as info:
        read_log(path)
    assert str(info.value).startswith(f"{path}:1:")
    assert "log format version 99 is not supported" in str(info.value)


def test_a_recorded_log_is_compact_json_one_object_per_line(tmp_path):
    _, log = _recorded(tmp_path)
    lines = log.read_text().splitlines()
    assert all(", " not in ln.split('"interface_text"')[0] and '": ' not in ln
               for ln in lines[1:])
    assert lines[1] == '{"step":0,"event":{"type":"mouse","x":1.0,"y":0.5}}'


# -- scripts ---------------------------------------------------------------------------------
def test_a_scripted_key_is_pressed_then_released_after_its_hold():
    from puppet.timeline.script import ScriptSpec, compile_script

    spec = ScriptSpec.model_validate({"events": [{"t": 1.0, "key": "a", "hold": 0.5}]})
    got = compile_script(spec, 1 / 480)
    assert got == [(480, ev.key("a", True)), (720, ev.key("a", False))]


# -- the BVH hierarchy -----------------------------------------------------------------------
def test_the_bvh_offsets_add_up_to_every_joints_anchor_on_the_cat():
    """Each joint's offset is from its parent's anchor: summed from the root, they put
    every joint on its anchor (the cat's knees hang off hips that are not at x = 0)."""
    from puppet.timeline.motion import planar_hierarchy

    spec = load_setup("cat-trot").character
    joints = {j.name: j for j in planar_hierarchy(spec)}
    anchor = {j.child: tuple(j.anchor) for j in spec.joints}
    for name, j in joints.items():
        if j.parent is None:
            continue
        x = y = 0.0
        k = j
        while k.parent is not None:
            x, y = x + k.offset[0], y + k.offset[1]
            k = joints[k.parent]
        assert (x, y) == pytest.approx(anchor[name], abs=1e-12), name
    assert any(abs(anchor[j.parent][0]) > 0.05 for j in joints.values()
               if j.parent in anchor)  # some offsets are from an off-centre parent


BOXES = """
name: boxes
description: a base and a leaf link that is a rotated box (test character)
links:
  - name: base
    mass: 5.0
    shapes: [{type: box, center: [0.0, 0.05], size: [0.4, 0.1]}]
  - name: flap
    mass: 1.0
    shapes:
      - {type: box, center: [0.0, 0.3], size: [0.1, 0.4], angle: 30}
      - {type: segment, a: [0.0, 0.1], b: [0.02, 0.15], radius: 0.01}   # a short one last
joints:
  - {name: hinge, parent: base, child: flap, anchor: [0.0, 0.1], limits: [-80, 80],
     pd: {stiffness: 40, damping: 1.0, max_torque: 60}}
"""
ONE = """
name: one
description: a single box and no joints (test character)
links:
  - name: block
    mass: 2.0
    shapes: [{type: box, center: [0.1, 0.2], size: [0.2, 0.1]}]
"""


def _corners(cx, cy, w, h, deg):
    a = math.radians(deg)
    return [(cx + math.cos(a) * x - math.sin(a) * y, cy + math.sin(a) * x + math.cos(a) * y)
            for x, y in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2))]


def test_a_box_ended_leaf_ends_at_its_farthest_rotated_corner(tmp_path):
    """Of all its shapes' points: here a rotated box's corner, not the short segment
    listed after it."""
    from puppet.timeline.motion import planar_hierarchy

    (tmp_path / "boxes.yaml").write_text(BOXES)
    spec = load_character(tmp_path / "boxes.yaml")
    flap = next(j for j in planar_hierarchy(spec) if j.name == "flap")
    far = max(_corners(0.0, 0.3, 0.1, 0.4, 30), key=lambda p: math.dist(p, (0.0, 0.1)))
    assert flap.end == pytest.approx((far[0], far[1] - 0.1), abs=1e-12)


def test_a_lone_root_link_ends_at_its_farthest_point_from_the_origin(tmp_path):
    from puppet.timeline.motion import planar_hierarchy

    (tmp_path / "one.yaml").write_text(ONE)
    try:
        spec = load_character(tmp_path / "one.yaml")
    except DataError as exc:  # a character needs a joint: nothing to test then
        pytest.skip(str(exc))
    (root,) = planar_hierarchy(spec)
    far = max(_corners(0.1, 0.2, 0.2, 0.1, 0), key=lambda p: math.hypot(*p))
    assert root.end == pytest.approx(far, abs=1e-12)


# -- the scrub preview after a branch --------------------------------------------------------
def _pose(session):
    return [(tuple(b.position), b.angle) for b in session.character.bodies.values()]


def test_the_preview_after_a_branch_shows_the_new_branch_not_the_cached_old_one():
    from puppet.session.history import Scrubber

    def played():
        s = Session(load_setup("luxo-mouse"))
        for k in range(180):
            s.handle(ev.mouse(0.5 + 0.4 * math.sin(k / 9), 0.5 + 0.3 * math.cos(k / 7)))
            s.advance(8)
        return s

    live, ref = played(), played()
    scrub = Scrubber(live)
    scrub.start()
    for _ in range(40):  # back about 0.7 s, filling the preview's cache on the way
        scrub.update(1 / 60)
    scrub.release()
    at = live.steps
    for k in range(40):  # new input: the history branches here
        for s in (live, ref):
            if k == 0:
                s.rewind_to(at) if s is ref else None
            s.handle(ev.mouse(0.1, 0.9))
            s.advance(8)
    scrub.start()
    checked = 0
    for frame in range(30):  # back into the new branch (the old one's steps, new poses)
        scrub.update(1 / 60)
        if live.steps > at and frame % 5 == 0:
            ref.rewind_to(live.steps)
            assert _pose(live) == _pose(ref), live.steps
            checked += 1
    scrub.release()
    assert checked >= 2


# -- the viewer's replay ---------------------------------------------------------------------
def test_the_viewer_is_told_only_of_the_app_actions_a_log_asks_for(tmp_path):
    from puppet.timeline.replay import LogFeeder

    iface = tmp_path / "t.yaml"
    iface.write_text(textwrap.dedent(IFACE))
    log = tmp_path / "a.jsonl"
    s = Session(load_setup(str(iface)))
    record_events(s, [(0, ev.mouse(0.2, 0.5)), (10, ev.action("checkpoint")),
                      (20, ev.mouse(0.8, 0.5))], 60, log)
    told = []
    feeder = LogFeeder(Session(load_setup(str(iface))), read_log(log), on_action=told.append)
    feeder.advance(100)
    assert None not in told
    assert np.isfinite(feeder.session.time)


# -- a log that cannot be read; the IK solver from outside the limits -----------------------
def test_a_log_path_through_a_file_says_why_it_cannot_be_read(tmp_path):
    (tmp_path / "notes.txt").write_text("not a folder")
    path = tmp_path / "notes.txt" / "run.jsonl"
    with pytest.raises(DataError) as info:
        read_log(path)
    assert str(info.value) == f"{path}: cannot read log: Not a directory"


def test_the_ik_solver_answers_within_the_limits_even_from_a_start_outside_them():
    from puppet.interface.ik import forward, solve_dls

    links = [(0.0, 0.2), (0.0, 0.15), (0.0, 0.1)]
    limits = [(-1.0, 1.0), (-0.5, 0.5), None]
    start = [1.6, -0.9, 0.3]  # the first two past their limits
    _, end = forward(links, start)
    q = solve_dls(links, end, start, limits)  # a target the start already reaches
    assert -1.0 <= q[0] <= 1.0 and -0.5 <= q[1] <= 0.5


def test_a_bare_log_name_is_found_among_the_saved_recordings(tmp_path, monkeypatch):
    """assets/logs/ first, then recordings/ (where the window saves its sessions)."""
    from puppet.data import catalog
    from puppet.timeline.replay import find_log

    monkeypatch.setitem(catalog.FOLDERS, "recording", (str(tmp_path), ".jsonl"))
    shutil.copy(LOGS / "luxo-hop.jsonl", tmp_path / "my-take.jsonl")
    assert find_log("my-take") == str(tmp_path / "my-take.jsonl")
    assert find_log("luxo-hop") == str(LOGS / "luxo-hop.jsonl")
    with pytest.raises(DataError) as info:
        find_log("no-such-take")
    assert "no log named 'no-such-take'" in str(info.value)
