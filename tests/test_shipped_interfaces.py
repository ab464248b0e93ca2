"""Every shipped interface passes `puppet check`, plays, and draws its key map."""

from pathlib import Path

import pytest

from puppet.app.describe import control_rows, live_keys
from puppet.commands.check import check_file
from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session

INTERFACES = sorted((Path(__file__).parents[1] / "interfaces").glob("*.yaml"))


@pytest.mark.parametrize("path", INTERFACES, ids=[p.stem for p in INTERFACES])
def test_shipped_interface_checks_and_plays_every_key(path):
    assert check_file(path) == "interface"
    session = Session(load_setup(str(path)))
    for binding in session.setup.interface.keys:
        session.handle(ev.key(binding.key, True))
        session.handle(ev.key(binding.key, False))
        session.advance(60)
    assert not session.sim.blown_up()
    spec, runtime = session.setup.interface, session.runtime
    shown = {k for k, _ in control_rows(spec, runtime.state, runtime.mode)}  # as on F1
    assert {k.key for k in live_keys(spec, runtime.state)} <= shown
    assert control_rows(spec, runtime.state, runtime.mode, "f1: all")  # the compact list


def test_luxo_keys_hop_key_rolls_luxo_over_when_it_lies_on_its_back():
    session = Session(load_setup("luxo-keys"))
    assert session.runtime.state == "upright"
    c = session.character
    c.place(0.0, 0.6, 3.1, c.start_joint_angles())  # upside down, above the floor
    session.advance(480)
    assert session.runtime.state == "on_back"
    assert session.runtime.binding("q").sequence == "roll_over"
    session.handle(ev.key("q", True))
    assert session.runtime.sequence.name == "roll_over"


def test_key_map_names_the_live_state_and_lists_each_key_once():
    """The HUD's controls panel, compact and on the help key, lists each key live in a
    state once (a state's own key, not the top level's it rebinds)."""
    from puppet.app.describe import where_line
    from puppet.data.catalog import load_setup

    spec = load_setup("luxo-keys").interface
    assert spec.states, "luxo-keys has a state machine"
    for state in spec.states:
        for more in (None, "f1: all"):
            keys = [k for k, text in control_rows(spec, state, None, more)
                    if k and text and k != "..." and not k.startswith("mouse")]
            assert len(keys) == len(set(keys)), (state, more, keys)
        assert f"state {state}" in where_line(spec, state, None)
