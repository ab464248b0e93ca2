"""Targets in another frame than the parent link's: a frame map holding a link at an
angle in the world or relative to another link, re-solved at the control rate; a key
setting a joint relative to another link."""

from __future__ import annotations

import math
import textwrap

import pytest
from helpers import session_of, tap

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session

LUXO_HEADER = "name: t\ndescription: a test interface\ncharacter: luxo\n"


def luxo_session(tmp_path, body: str) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(LUXO_HEADER + textwrap.dedent(body))
    return Session(load_setup(str(path)))


@pytest.mark.parametrize("frame", ["world", "lower_arm"])
def test_a_frame_map_holds_the_link_at_its_angle_in_that_frame(tmp_path, frame):
    s = luxo_session(tmp_path, f"""
    maps:
      - {{input: mouse.x, joint: knee, frame: {frame}, to: [0, 60]}}
    poses:
      lean: {{joints: {{ankle: -30}}}}
    keys:
      - {{key: l, pose: lean}}
    """)
    tap(s, "l")  # the lower arm leans: its frame and the world's differ by 30 degrees
    s.handle(ev.mouse(0.5, 0.5))  # 30 degrees
    s.advance(960)
    c = s.character
    ref = 0.0 if frame == "world" else c.bodies["lower_arm"].angle
    got = math.degrees(c.bodies["upper_arm"].angle - ref)
    assert abs(math.degrees(c.bodies["lower_arm"].angle)) > 15
    assert got == pytest.approx(30, abs=8), got  # the servo sags a little under gravity


def test_a_frame_target_is_re_solved_at_the_control_rate_not_every_step(tmp_path):
    s = luxo_session(tmp_path, """
    control_rate: 60
    maps:
      - {input: mouse.x, joint: knee, frame: world, to: [0, 60]}
    poses:
      lean: {joints: {ankle: -30}}
    keys:
      - {key: l, pose: lean}
    """)
    s.handle(ev.mouse(0.5, 0.5))
    tap(s, "l")  # the lower arm swings over: the knee's target must follow it
    knee = s.character.servos["knee"]
    changed = []
    last = knee.target
    for _ in range(240):  # 0.5 s: the lamp moves, so the solved target keeps changing
        s.advance(1)
        if knee.target != last:
            changed.append(s.steps)
            last = knee.target
    period = round(480 / 60)
    assert len(changed) > 10
    assert all((step - 1) % period == 0 for step in changed), changed[:12]


def test_a_key_sets_a_joint_relative_to_another_link(tmp_path):
    s = session_of(tmp_path, """
    name: t
    description: the chest held 10 degrees forward of the pelvis by a key
    character: biped
    keys:
      - {key: z, set: {waist: {relative_to: pelvis, angle: -10}}}
    """)
    s.advance(240)
    tap(s, "z")
    s.advance(480)
    b = s.character.bodies
    rel = math.degrees(b["chest"].angle - b["pelvis"].angle)
    # the waist's parent is the pelvis: its target is the angle itself, which the servo
    # holds within a couple of degrees under the chest's weight
    assert math.degrees(s.character.servos["waist"].target) == pytest.approx(-10.0, abs=1e-9)
    assert rel == pytest.approx(-10.0, abs=3.0)


@pytest.mark.parametrize("how", ["c", "python"])
def test_a_frame_maps_holder_holds_as_hold_does(tmp_path, how, path_of):
    """``FrameTargets.holder`` (a frame map's hold at each mouse event, its lookups made
    once) leaves what ``hold`` leaves: the held targets, the owner table, the servo's
    target to the bit, on either path, and after a checkpoint and a restore."""
    from puppet.interface.ownership import FEEDBACK
    from puppet.interface.poses import FrameTarget

    path_of(how)
    s = luxo_session(tmp_path, """
    maps:
      - {input: mouse.x, joint: knee, frame: world, to: [0, 60]}
    """)
    s.handle(ev.mouse(0.3, 0.5))
    s.advance(100)
    frames = s.runtime.frames
    for joint, ref, parent, owner in (("knee", None, False, None),
                                      ("ankle", "lower_arm", True, FEEDBACK)):
        holder = frames.holder(joint, ref, parent, owner)
        for angle in (0.3, -1.25):
            got = []
            for by_holder in (False, True):
                if by_holder:
                    holder(angle)
                else:
                    frames.hold(joint, FrameTarget(ref, angle, parent), owner)
                got.append((repr(frames.held), dict(frames.owners_table.table),
                            s.character.servos[joint].target))
                s.character.servos[joint].target = 0.0
            assert got[0] == got[1]
            s.advance(40)
        s.perform("checkpoint")
        s.advance(10)
        s.perform("restore")
        s.advance(30)  # (the bodies of before the checkpoint stood still)
        frames = s.runtime.frames
        holder(0.7)
        after = s.character.servos[joint].target
        frames.hold(joint, FrameTarget(ref, 0.7, parent), owner)
        assert s.character.servos[joint].target == after
