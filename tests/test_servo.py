"""PD servos track targets with stiffness, damping and a torque limit, stably."""

import math
import random

import pytest

from puppet.data.catalog import load_setup
from puppet.session import Session


@pytest.fixture
def session():
    return Session(load_setup("luxo-mouse"))


def test_servo_reaches_a_new_target(session):
    servo = session.character.servos["knee"]
    servo.target = math.radians(90)
    session.advance(480)
    assert abs(math.degrees(servo.angle) - 90) < 3


def test_target_stiffness_and_damping_change_at_any_step(session):
    servo = session.character.servos["knee"]
    servo.target = math.radians(100)
    session.advance(3)
    servo.stiffness = 0.0
    servo.damping = 0.0
    assert servo.stiffness == 0.0 and servo.damping == 0.0
    angle = servo.angle
    session.advance(240)
    # With no stiffness the servo no longer pulls toward 100 deg: gravity folds the lamp.
    assert abs(math.degrees(servo.angle) - 100) > 10 or abs(servo.angle - angle) > 0.2


@pytest.mark.parametrize("damping", [0.0, 0.45])
def test_torque_never_exceeds_the_limit(session, damping):
    servo = session.character.servos["ankle"]
    servo.max_torque = 2.0
    servo.damping = damping
    servo.target = math.radians(-80)
    torques = []
    for _ in range(200):
        session.advance(1)
        torques.append(abs(servo.torque(session.sim.dt)))
    assert max(torques) <= 2.0 + 1e-9
    if damping == 0.0:
        assert max(torques) > 1.99  # the spring alone asks for far more: it saturates


def test_weak_servo_cannot_hold_what_a_strong_one_can(session):
    strong = Session(load_setup("luxo-mouse"))
    for s, limit in ((session, 0.3), (strong, 20.0)):
        servo = s.character.servos["ankle"]
        servo.max_torque = limit
        servo.target = math.radians(-60)
        s.advance(480)
    assert abs(math.degrees(strong.character.servos["ankle"].angle) + 60) < 5
    assert abs(math.degrees(session.character.servos["ankle"].angle) + 60) > 15


def test_hopping_gains_stay_stable_under_random_targets(session):
    """Slam random targets at the hopping gains for 20 s: no blow-up, no NaN."""
    rng = random.Random(7)
    for _ in range(100):
        for servo in session.character.servos.values():
            servo.target = math.radians(rng.uniform(-85, 160))
        session.advance(96)
        assert not session.sim.blown_up()


@pytest.mark.parametrize("offset", [0.6, -0.6])
def test_the_servo_torque_has_the_sign_of_the_push_toward_its_target(offset):
    s = Session(load_setup("luxo-mouse"))
    s.advance(240)
    servo = s.character.servos["knee"]
    servo.target = servo.angle + offset
    before = servo.velocity
    s.advance(1)
    torque = servo.torque(s.sim.dt)
    assert abs(torque) > 0.5
    assert math.copysign(1, torque) == math.copysign(1, offset)
    # and the joint speeds up that way
    assert math.copysign(1, servo.velocity - before) == math.copysign(1, offset)
