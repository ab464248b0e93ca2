"""The balance overlay (F4, --overlay com): centre of mass, its ground point, the
support between the outermost ground contacts, the extrapolated centre of mass."""

import math

import pytest

from puppet.data import catalog
from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.physics.balance import balance, ground_contacts
from puppet.session import Session


def _one_interface_per_character() -> list[str]:
    """Each character's standing interface (NAME-stand) if it has one, else its first."""
    by_character: dict[str, list[str]] = {}
    for n, _ in catalog.list_kind("interface"):
        by_character.setdefault(load_setup(n).character.name, []).append(n)
    return sorted(f"{c}-stand" if f"{c}-stand" in names else names[0]
                  for c, names in by_character.items())


CHARACTERS = _one_interface_per_character()


def _balance(session):
    scene = session.setup.scene
    return balance(session.character, scene.gravity, scene.ground_height)


@pytest.mark.parametrize("interface", CHARACTERS)
def test_standing_still_the_com_is_over_the_support(interface):
    session = Session(load_setup(interface))
    session.advance(480)  # settle
    b = _balance(session)
    assert b.support is not None and b.support[1] - b.support[0] > 0.05
    assert b.support[0] < b.com[0] < b.support[1]
    assert b.inside and abs(b.xcom - b.com[0]) < 0.02  # at rest xcom is the com
    assert b.ground_y == pytest.approx(session.setup.scene.ground_height(b.com[0]))


def test_xcom_leads_the_com_by_its_speed_and_a_flight_has_no_support():
    # replay the hop a few steps at a time, through its flights
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, find_log, new_session, setup_for_log

    log = read_log(find_log("luxo-hop"))
    session = new_session(log, setup_for_log(log, False)[0])
    feeder = LogFeeder(session, log)
    flights = 0
    while not feeder.finished:
        feeder.advance(8)
        b = _balance(session)
        vx = session.character.com_velocity()[0]
        g = math.hypot(*session.setup.scene.gravity)
        assert b.xcom == pytest.approx(b.com[0] + vx * math.sqrt((b.com[1] - b.ground_y) / g))
        if not ground_contacts(session.character):
            flights += 1
            assert b.support is None and b.inside is None
    assert flights > 5  # the hop leaves the ground


def test_the_overlay_key_is_the_windows_and_drawing_it_does_not_change_the_run(tmp_path):
    from puppet.app.headless import run_headless
    from puppet.timeline.script import compile_script, load_script

    session = Session(load_setup("cat-trot"))
    assert session.handle(ev.key("f4", True)) == "balance"  # the window toggles it
    setup = load_setup("cat-trot")
    events = compile_script(load_script(catalog.find("script", "cat-trot")), 1 / 480)
    plain = run_headless(setup, events, 1.0)
    drawn = run_headless(setup, events, 1.0, frames_dir=str(tmp_path / "f"), fps=10,
                         size=(320, 200), overlay=True)
    assert drawn.sim.state_hash() == plain.sim.state_hash()


def test_video_export_draws_the_overlay(tmp_path, monkeypatch):
    import puppet.app.render as render
    from puppet.app.export import export_video
    from puppet.timeline.replay import find_log

    drawn = []
    real = render.draw_balance
    monkeypatch.setattr(render, "draw_balance", lambda *a, **k: (drawn.append(1), real(*a, **k)))
    for overlay in (False, True):
        video = export_video(find_log("luxo-hop"), tmp_path / f"v{overlay}.gif", fps=10,
                             size=(320, 192), hold=0, until_step=240, progress=False,
                             overlay=overlay)
        assert len(drawn) == (video.frames if overlay else 0)
