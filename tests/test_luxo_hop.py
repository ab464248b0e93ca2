"""A scripted mouse gesture makes Luxo hop: off the ground, upright again, further along."""

from tests.helpers import run_script


def test_mouse_gesture_hops_luxo_forward_on_flat_floor():
    run = run_script("luxo-hop", "luxo-mouse", "flat")
    s = run.samples
    start_x, start_bottom = s[0]["base_x"], s[0]["base_bottom"]
    # Airborne: the whole lamp off the floor for a stretch (not a shuffle or a slide).
    airborne = [x for x in s if not x["touching"]]
    assert len(airborne) * 4 / 480 >= 0.1, "Luxo never left the ground for 0.1 s"
    assert max(x["base_bottom"] for x in s) - start_bottom >= 0.03
    # Lands upright, at least 0.5 m further along.
    assert s[-1]["upright"] and s[-1]["base_contact"]
    assert s[-1]["base_x"] - start_x >= 0.5
    # Upright after each landing (it does not fall and get up again).
    for t in (1.9, 3.7, 4.5):
        nearest = min(s, key=lambda x: abs(x["t"] - t))
        assert nearest["upright"], f"not upright at t={t}"


def test_without_the_gesture_luxo_stays_put():
    """The hop comes from the input, not from the scene or the start pose."""
    from puppet.data.catalog import load_setup
    from puppet.session import Session

    session = Session(load_setup("luxo-mouse"))
    x0 = session.character.bodies["base"].position.x
    session.advance(round(4.5 / session.sim.dt))
    assert abs(session.character.bodies["base"].position.x - x0) < 0.01
    assert session.character.upright()
