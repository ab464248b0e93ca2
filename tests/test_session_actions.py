"""Ctrl+drag and reset act through Session.handle, the path the window uses too."""

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session


def test_drag_spring_pulls_a_body_toward_the_cursor():
    session = Session(load_setup("luxo-mouse"))
    base = session.character.bodies["base"]
    x0 = base.position.x
    session.handle(ev.drag_start("upper_arm", (0.0, 0.43), (x0 + 0.6, 0.6)))
    session.advance(480)
    assert base.position.x > x0 + 0.3
    session.handle(ev.drag_end())
    assert session.sim.drag_spring is None


def test_reset_key_returns_to_the_start_pose():
    session = Session(load_setup("luxo-mouse"))
    start = session.sim.state_vector()
    session.handle(ev.mouse(1.0, 0.0))
    session.advance(480)
    assert session.sim.state_vector() != start
    assert session.handle(ev.key("r", True)) is None  # a sim action, done by the session
    assert session.sim.state_vector() == start
    assert session.steps == 480  # time goes on; reset is an event, not a rewind


def test_app_keys_come_back_as_app_actions():
    session = Session(load_setup("luxo-mouse"))
    assert session.handle(ev.key("p", True)) == "pause"
    assert session.handle(ev.key("escape", True)) == "quit"
    assert session.handle(ev.key("-", True)) == "slower"


def test_a_drag_held_at_a_checkpoint_is_back_after_restore_and_pulls_alike():
    def start():
        s = Session(load_setup("luxo-mouse"))
        s.advance(120)
        x = s.character.bodies["base"].position.x
        s.handle(ev.drag_start("upper_arm", (0.0, 0.43), (x + 0.6, 0.6)))
        s.advance(60)
        s.handle(ev.action("checkpoint"))
        return s, x

    straight, x0 = start()
    at = straight.steps
    straight.advance(360)
    want = straight.sim.state_hash()
    assert straight.character.bodies["base"].position.x > x0 + 0.1  # it pulls

    s, _ = start()
    s.handle(ev.drag_end())
    s.advance(200)
    assert s.sim.drag_spring is None
    s.handle(ev.action("restore"))
    assert s.steps == at and s.sim.drag_spring is not None
    s.advance(360)
    assert s.sim.state_hash() == want
