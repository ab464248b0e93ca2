"""Scenes: the ground's top and the start height over a gap, props (a ball, a dynamic
prop of several shapes, a bar hanging from its pivot across restores), and a character
joint with no start angle."""

from __future__ import annotations

import math
import textwrap

import pytest
from helpers import session_of

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session

PENDULUM = """
name: t
description: the pendulum scene, mouse on the knee
character: luxo
scene: pendulum
maps:
  - {input: mouse.y, joint: knee, from: [0, 1], to: [0, 90]}
"""


def test_a_circle_prop_is_a_ball_that_rests_on_the_floor(tmp_path):
    scene = tmp_path / "ball.yaml"
    scene.write_text(textwrap.dedent("""\
        name: ball
        description: a ball dropped ahead of Luxo
        ground:
          - points: [[-10.0, 0.0], [10.0, 0.0]]
        props:
          ball:
            body: dynamic
            mass: 0.2
            position: [0.8, 0.5]
            shapes:
              - {circle: [0.0, 0.0], radius: 0.05}
        """))
    s = Session(load_setup("luxo-mouse", str(scene)))
    ball = s.sim.props["ball"]
    assert [type(sh).__name__ for sh in ball.shapes] == ["Circle"]
    assert ball.shapes[0].radius == 0.05
    s.advance(960)  # 2 s: fallen and settled
    # on the floor (whose segments have a little thickness of their own), at rest
    assert 0.045 < ball.body.position.y < 0.07
    assert abs(ball.body.velocity.y) < 0.01


def test_a_hanging_bar_still_hangs_from_its_pivot_after_two_restores(tmp_path):
    straight = session_of(tmp_path, PENDULUM)  # the same checkpoints, no detours
    for at in (300, 700):
        straight.advance(at - straight.steps)
        straight.handle(ev.action("checkpoint"))
    straight.advance(1400 - straight.steps)
    want = straight.sim.state_hash()
    s = session_of(tmp_path, PENDULUM)
    for back_at in (300, 700):  # a checkpoint, a detour, back; twice
        s.advance(back_at - s.steps)
        s.handle(ev.action("checkpoint"))
        s.advance(150)
        s.handle(ev.action("restore"))
        assert s.steps == back_at
        assert s.sim.props["swing"].pin is not None
    s.advance(1400 - s.steps)
    assert s.sim.state_hash() == want
    bar = s.sim.props["swing"].body
    top = bar.local_to_world((0.0, 0.0))
    assert math.dist(top, (0.06, 0.88)) < 1e-3  # hanging where the scene pins it


def test_a_character_that_starts_over_a_gap_starts_at_the_scenes_start_height(tmp_path):
    scene = tmp_path / "gap.yaml"
    scene.write_text(textwrap.dedent("""\
        name: gap
        description: Luxo starts over a gap, 0.5 m up
        ground:
          - points: [[-10.0, 0.0], [-1.0, 0.0]]
          - points: [[1.0, 0.0], [10.0, 0.0]]
        start: {x: 0.0, y: 0.5}
        """))
    s = Session(load_setup("luxo-mouse", str(scene)))
    assert s.setup.scene.ground_height(0.0) is None
    assert s.character.lowest_point() == pytest.approx(0.502, abs=1e-6)


def test_a_dynamic_prop_of_several_shapes_weighs_its_mass(tmp_path):
    scene = tmp_path / "dumbbell.yaml"
    scene.write_text(textwrap.dedent("""\
        name: dumbbell
        description: a 0.4 kg dumbbell of two balls and a bar, ahead of Luxo
        ground:
          - points: [[-10.0, 0.0], [10.0, 0.0]]
        props:
          dumbbell:
            body: dynamic
            mass: 0.4
            position: [0.8, 0.3]
            shapes:
              - {circle: [-0.1, 0.0], radius: 0.04}
              - {circle: [0.1, 0.0], radius: 0.04}
              - {segment: [[-0.1, 0.0], [0.1, 0.0]], radius: 0.01}
        """))
    s = Session(load_setup("luxo-mouse", str(scene)))
    body = s.sim.props["dumbbell"].body
    assert body.mass == pytest.approx(0.4)
    assert body.center_of_gravity.x == pytest.approx(0.0, abs=1e-9)


def test_a_joint_with_no_start_angle_starts_straight(tmp_path):
    from puppet.data.catalog import ROOT

    text = (ROOT / "characters" / "luxo.yaml").read_text(encoding="utf-8")
    assert "joints: {ankle: -25, knee: 55}" in text
    character = tmp_path / "luxo.yaml"
    character.write_text(text.replace("joints: {ankle: -25, knee: 55}", "joints: {ankle: -25}"))
    s = session_of(tmp_path, f"""
    name: t
    description: luxo with no start angle for the knee
    character: {character}
    """)
    knee = s.character.servos["knee"]
    assert knee.target == 0.0 and knee.angle == pytest.approx(0.0, abs=1e-9)
    assert math.degrees(s.character.servos["ankle"].target) == pytest.approx(-25)


def test_the_grounds_top_is_its_line_plus_half_its_thickness():
    s = Session(load_setup("biped-stand"))
    ground = s.setup.scene.ground[0]
    assert s.sim.ground_surface(1.0) == pytest.approx(ground.points[0][1] + ground.thickness / 2)
