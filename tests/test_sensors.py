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


def test_lead_is_how_far_one_link_is_ahead_of_another():
    """``lead.LINK.OTHER``: LINK's centre of mass minus OTHER's, in x only (m); the
    swing foot's lead over the stance foot in a walk."""
    s = Session(load_setup("biped-stand"))
    s.advance(120)
    c = s.character
    for a, b in (("foot_near", "foot_far"), ("head", "foot_near"), ("chest", "pelvis")):
        got = reader(f"lead.{a}.{b}", c)()
        assert got == pytest.approx(c.link_position(a)[0] - c.link_position(b)[0], abs=1e-12)
        assert reader(f"lead.{b}.{a}", c)() == pytest.approx(-got, abs=1e-12)
    assert abs(reader("lead.head.foot_near", c)()) < 0.3  # the head is 1.5 m up: x only


def test_lead_with_roles_reads_the_bound_links(tmp_path):
    """Both links of ``lead.`` may be roles: in the binding ``near`` the swing foot is
    foot_far and the stance foot foot_near. Standing, the far foot is 12 cm behind the
    near one: a transition on the lead past -0.09 m does not fire, one past -0.15 m does."""
    text = """
    name: t
    description: a state whose exit waits for the far foot's lead over the near one
    character: biped
    roles:
      stance_foot: {near: foot_near, far: foot_far}
      swing_foot:  {near: foot_far, far: foot_near}
    initial: near
    states:
      near:
        roles: near
        transitions:
          - {to: ahead, when: {sensor: lead.swing_foot.stance_foot, above: LIMIT}}
      ahead: {}
    """
    for limit, fires in ((-0.09, False), (-0.15, True)):
        s = session_of(tmp_path, text.replace("LIMIT", str(limit)))
        assert s.runtime.roles.sensor("lead.swing_foot.stance_foot") == "lead.foot_far.foot_near"
        s.advance(240)
        c = s.character
        lead = c.link_position("foot_far")[0] - c.link_position("foot_near")[0]
        assert -0.15 < lead < -0.09
        assert (s.runtime.state == "ahead") == fires, limit


def test_a_lead_sensor_naming_an_unknown_link_is_refused(tmp_path):
    from puppet.data.errors import DataError

    with pytest.raises(DataError, match="lead|link"):
        session_of(tmp_path, """
        name: t
        description: a typo in a lead sensor
        character: biped
        initial: a
        states:
          a:
            transitions:
              - {to: b, when: {sensor: lead.foot_nare.foot_far, above: 0.1}}
          b: {}
        """)


def test_com_fall_time_is_the_free_flights_time_down_to_y_0():
    """``com.fall_time``: Luxo thrown up reads (vy + sqrt(vy^2 + 2 g y)) / g, and the
    reading counts down with the flight: checked against where the centre of mass
    really is that long after (it flies freely, joints held)."""
    s = Session(load_setup("luxo-mouse-strong"))
    s.advance(60)
    c = s.character
    for b in c.bodies.values():  # up 1 m and thrown up at 1.5 m/s
        b.position = (b.position.x, b.position.y + 1.0)
        b.velocity = (0.0, 1.5)
    read = reader("com.fall_time", c)
    y, vy = c.com()[1], c.com_velocity()[1]
    g = -c.bodies["base"].space.gravity[1]
    t = read()
    assert t == pytest.approx((vy + math.sqrt(vy * vy + 2 * g * y)) / g, rel=1e-12)
    assert 0.6 < t < 1.0
    steps = round(0.5 * t / s.sim.dt)  # half way down the flight
    s.advance(steps)
    assert read() == pytest.approx(t - steps * s.sim.dt, abs=0.01)
    s.advance(round(t / s.sim.dt))  # landed: at rest on the floor its COM is above y 0
    assert 0.0 < read() < 0.3


def test_com_spin_is_the_whole_bodys_spin_and_keeps_in_the_air():
    """``com.spin``: the angular momentum about the centre of mass over the moment of
    inertia there (deg/s in a map). A figure spun as a rigid body reads that spin; in the
    air, with the joints moving, a link's spin changes but the body's does not."""
    s = Session(load_setup("biped-stand"))
    s.advance(60)
    c = s.character
    cx, cy = c.com()
    w = 2.0  # rad/s, counter-clockwise: every link turned as one rigid body, 3 m up
    for b in c.bodies.values():
        px, py = b.local_to_world(b.center_of_gravity)
        b.position = (b.position.x, b.position.y + 3.0)
        b.velocity = (-w * (py - cy), w * (px - cx))
        b.angular_velocity = w
    read = reader("com.spin", c)
    assert read() == pytest.approx(w, rel=1e-9)
    for j in ("hip_near", "knee_near", "waist"):  # the servos fold the body in the air
        c.servos[j].target = c.servos[j].target + 1.0
    s.advance(60)
    assert abs(c.bodies["thigh_near"].angular_velocity - w) > 0.2  # a link's spin changed
    assert read() == pytest.approx(w, rel=0.02)  # the body's did not


def test_torque_is_what_the_servo_puts_on_its_child():
    """``torque.JOINT`` (N*m): stiffness * (target - angle) - damping * relative spin,
    within the cap: the torque the gains ask for (the solver's implicit damping then
    takes part of it within a step). A hip 20 deg off its target reads the spring's pull,
    its sign the way the joint then turns, and a target far off reads the cap."""
    s = Session(load_setup("biped-stand"))
    s.advance(240)
    c = s.character
    read = reader("torque.hip_near", c)
    hip = c.servos["hip_near"]
    for off, sign in ((math.radians(20), 1.0), (math.radians(-20), -1.0)):
        hip.target = hip.angle + off
        a, b = c.bodies["thigh_near"], c.bodies["pelvis"]
        want = hip.stiffness * (hip.target - hip.angle) - hip.damping * (
            a.angular_velocity - b.angular_velocity)
        got = read()
        assert got == pytest.approx(max(-hip.max_torque, min(hip.max_torque, want)), rel=1e-12)
        assert sign * got > 200.0
        before = hip.angle
        s.advance(4)
        assert sign * (hip.angle - before) > 0.0  # it turns the way the torque says
    hip.target = hip.angle + math.radians(90)
    assert read() == hip.max_torque


def test_a_torque_sensor_names_a_joint(tmp_path):
    from puppet.data.errors import DataError

    with pytest.raises(DataError, match="joint 'hip_nare'"):
        session_of(tmp_path, """
        name: t
        description: a typo in a torque sensor
        character: biped
        maps:
          - {input: sensor.torque.hip_nare, joint: hip_far, from: [0, 1], to: [0, 0.05],
             combine: add}
        """)
