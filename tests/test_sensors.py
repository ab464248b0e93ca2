"""Sensor inputs: ``com.dx`` of a link and of the support (the centre of mass's offset),
and a sensor map that sets a target following its sensor."""

from __future__ import annotations

import math

import pytest
from helpers import session_of

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.interface.conditions import reader
from puppet.session import Session


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
    s = session_of(tmp_path, """
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


def test_com_dx_support_is_the_offset_from_the_middle_of_the_feet():
    s = Session(load_setup("biped-stand"))
    s.advance(240)
    c = s.character
    lo, hi = c.support_extent()
    got = reader("com.dx.support", c)()
    assert got == pytest.approx(c.com()[0] - 0.5 * (lo + hi), abs=1e-12)
    assert abs(got) < 0.1 and hi - lo > 0.1  # standing: over the middle of the feet
    s.sim.character.bodies["pelvis"].position = (0.0, 5.0)  # nothing touches
    for b in s.character.bodies.values():
        b.position = (b.position.x, b.position.y + 3.0)
    s.advance(1)
    assert reader("com.dx.support", c)() == 0.0
