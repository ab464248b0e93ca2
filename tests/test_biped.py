"""The human figure: its body table, and that it stands with its targets held."""

import importlib.util
import math
from pathlib import Path

import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session

ROOT = Path(__file__).resolve().parents[1]


def _make_biped():
    spec = importlib.util.spec_from_file_location("make_biped", ROOT / "tools" / "make_biped.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_character_files_are_what_the_body_table_writes():
    for path, text in _make_biped().files().items():
        assert path.read_text() == text, f"{path.name}: run tools/make_biped.py"


@pytest.mark.parametrize("interface, height, mass", [("biped-stand", 1.75, 70.0),
                                                     ("biped-small-stand", 1.0, 20.0)])
def test_body_has_the_tables_mass_and_a_human_centre_of_mass(interface, height, mass):
    session = Session(load_setup(interface))
    c = session.character
    assert sum(b.mass for b in c.bodies.values()) == pytest.approx(mass)
    floor = min(s.cache_bb().bottom for shapes in c.shapes.values() for s in shapes)
    top = max(s.cache_bb().top for shapes in c.shapes.values() for s in shapes)
    assert top - floor == pytest.approx(height, abs=0.01 * height)
    # a standing adult's centre of mass is at 0.55-0.58 of the height
    assert 0.54 <= (c.com()[1] - floor) / height <= 0.59
    # the thigh's centre of mass sits 0.433 of the way down from the hip (Winter)
    hip, knee = c.spec.joint("hip_near").anchor[1], c.spec.joint("knee_near").anchor[1]
    assert c.bodies["thigh_near"].center_of_gravity.y == pytest.approx(
        hip - 0.433 * (hip - knee), abs=1e-4)
    # knees bend one way, elbows the other
    assert c.spec.joint("knee_near").limits[1] == 0 and c.spec.joint("elbow_far").limits[0] == 0


def _tilt_over(session: Session, seconds: float) -> float:
    """Largest tilt of pelvis or chest from upright (degrees) over ``seconds``."""
    worst = 0.0
    for _ in range(round(seconds * 60)):
        session.advance(8)
        for link in ("pelvis", "chest"):
            a = math.remainder(session.character.bodies[link].angle, 2 * math.pi)
            worst = max(worst, abs(math.degrees(a)))
    return worst


@pytest.mark.parametrize("interface", ["biped-stand", "biped-small-stand"])
def test_figure_stands_ten_seconds_with_its_targets_held(interface):
    session = Session(load_setup(interface))
    assert _tilt_over(session, 10.0) < 3.0
    assert session.character.in_contact("foot_near") and session.character.in_contact("foot_far")


def test_figure_with_a_tenth_of_its_stiffness_falls():
    """The standing test can fail. (At 0.2x it still stands, sagging 8 deg: the ankles'
    and knees' damping, large beside the feet's and shanks' own inertia, all but
    locks them in this solver.)"""
    session = Session(load_setup("biped-stand"))
    for servo in session.character.servos.values():
        servo.stiffness *= 0.1
    assert _tilt_over(session, 10.0) > 45.0


def test_figure_stands_with_its_arms_up_and_knees_soft():
    session = Session(load_setup("biped-stand"))
    for key in ("3", "2"):
        session.handle(ev.key(key, True))
        session.handle(ev.key(key, False))
        assert _tilt_over(session, 3.0) < 12.0
    assert _tilt_over(session, 5.0) < 8.0


def test_a_checkpoint_of_the_figure_replays_the_run_that_never_restored():
    session = Session(load_setup("biped-stand"))
    session.handle(ev.key("3", True))
    session.advance(480)
    sim = session.sim
    data = sim.checkpoint()
    sim.step(960)
    straight = sim.state_vector()
    sim.restore(data)
    sim.step(960)
    assert sim.state_vector() == straight
    assert session.character.in_contact("foot_near")
