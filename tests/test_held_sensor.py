"""A script rule's ``held.CHAIN`` sensor: the height of the point a chain holds (NaN,
so no condition, while it holds nothing). The ladder climb's rules press each turn's key
after the limb before it has caught its rung (assets/scripts/biped-ladder-climb.yaml):
here the far hand's key waits for the near hand to hold rung 4, a rule watching rung 6
never fires, and a chain the interface lacks is refused at its line."""

from __future__ import annotations

import math

import pytest

from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.data.yamlfile import load_text
from puppet.interface.conditions import reader
from puppet.session import Session
from puppet.timeline.reactive import ScriptPlayer, Speed, play_script
from puppet.timeline.script import parse_script

DT = 1 / 480
RULES = """
interface: biped-ladder
seconds: 3
events:
  - {t: 0.5, key: g}
rules:
  - {when: [{state: hand_far_next}, {sensor: held.hand_near, above: 1.15, below: 1.25}],
     after: 0.3, key: g}
  - {when: {sensor: held.hand_near, above: 1.75}, after: 0.0, key: v}
"""


def test_a_rule_on_held_waits_for_the_catch():
    setup = load_setup("biped-ladder")
    session = Session(setup)
    presses: list[tuple[int, str]] = []
    session.listener = lambda step, e: presses.append((step, e["key"])) \
        if e["type"] == "key" and e["down"] else None
    caught = {"step": None}
    read = reader("held.hand_near", session.character, grasp_point=session.sim.grasp_point)
    assert math.isnan(read())  # nothing held yet: no condition holds

    def watch(s: Session) -> None:
        if caught["step"] is None and s.sim.grasp_point("hand_near") is not None:
            caught["step"] = s.steps

    spec = parse_script(load_text(RULES, "held.yaml"))
    speed = Speed(1.0)
    play_script(session, ScriptPlayer(session, spec, round(3.0 / DT), speed, speed.apply), 8,
                watch)
    assert abs(read() - 1.2) < 0.01  # rung 4, 1.2 m up
    assert [k for _, k in presses] == ["g", "g"]  # the rung-6 rule (v) never fired
    first, second = presses[0][0], presses[1][0]
    assert first == 240 and caught["step"] is not None and first < caught["step"]
    # seen at the first control poll (every 8 steps) from the catch, 0.3 s later
    assert 0 <= second - round(0.3 / DT) - caught["step"] < 8


def test_held_names_a_chain_of_the_interface(tmp_path):
    from tests.test_reactive import refusal

    message = refusal(tmp_path, "biped-ladder", "{sensor: held.hand_middle, above: 0.0}")
    assert "no chain 'hand_middle'" in message and "bad.yaml:3:" in message, message


def test_a_state_machine_is_told_held_is_for_scripts(tmp_path):
    """``held.CHAIN`` in an interface's map or transition is refused at its line, saying
    it belongs to a script's rules (not a bare 'unknown sensor')."""
    path = tmp_path / "bad.yaml"
    path.write_text("name: bad\ndescription: bad\ncharacter: biped\n"
                    "maps:\n  - {input: sensor.held.hand_near, joint: waist, to: [0, 1]}\n",
                    encoding="utf-8")
    with pytest.raises(DataError) as caught:
        load_setup(str(path))
    message = str(caught.value)
    assert "script's rules only" in message and f"{path}:5:" in message, message
