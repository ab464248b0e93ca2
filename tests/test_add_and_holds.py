"""A constant offset map (``add:``) while a state is active, and the load-time warning
for a world-frame hold that pushes against a light, free side."""

from __future__ import annotations

import math

import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session

LEAN = """name: lean
description: an offset while a state is active
character: luxo
keys:
  - {key: l, goto: leaning}
  - {key: u, goto: upright}
  - {key: s, set: {ankle: -35}}
states:
  upright: {}
  leaning:
    maps:
      - {joint: ankle, add: -20}
      - {joints: {knee: 1}, add: 10}
"""


def deg(session, joint):
    return math.degrees(session.character.servos[joint].target)


def test_an_add_map_offsets_whatever_writes_the_joint_while_its_state_is_active(tmp_path):
    path = tmp_path / "lean.yaml"
    path.write_text(LEAN)
    s = Session(load_setup(str(path)))
    assert (round(deg(s, "ankle"), 9), round(deg(s, "knee"), 9)) == (-25, 55)
    s.handle(ev.key("l"))
    s.advance(16)  # the next control step
    assert deg(s, "ankle") == pytest.approx(-45) and deg(s, "knee") == pytest.approx(65)
    s.handle(ev.key("s"))  # a new target: the offset is added to it
    s.advance(16)
    assert deg(s, "ankle") == pytest.approx(-55)
    s.handle(ev.key("u"))  # left: taken back
    s.advance(16)
    assert deg(s, "ankle") == pytest.approx(-35) and deg(s, "knee") == pytest.approx(55)


@pytest.mark.parametrize("line, says", [
    ("{joint: ankle, add: -20, input: mouse.x}", "it has no 'input' or 'to'"),
    ("{joint: ankle, add: -20, curve: smoothstep}", "no 'frame' or 'curve'"),
    ("{joint: ankle}", "a map needs 'input' and 'to'"),
])
def test_an_add_map_with_an_input_is_refused_in_one_line(tmp_path, line, says):
    path = tmp_path / "bad.yaml"
    path.write_text(LEAN.replace("{joint: ankle, add: -20}", line))
    with pytest.raises(DataError) as err:
        check_file(path)
    assert says in err.value.message and err.value.line == 12


TAIL = """name: cat-tail
description: the cat's hips held level through its tail
character: cat
scene: cat-flat
poses:
  level: {joints: {tail: {world: 0, hold: parent}}}
  stand_up: {joints: {hip_near: {world: 0, hold: parent}}}
keys:
  - {key: h, pose: level}
  - {key: j, pose: stand_up}
"""


def test_a_hold_against_a_light_free_side_is_a_warning_at_its_place(tmp_path, capsys):
    from puppet.commands import main

    path = tmp_path / "cat-tail.yaml"
    path.write_text(TAIL)
    warnings: list[str] = []
    assert check_file(path, warnings) == "interface"
    assert len(warnings) == 1, warnings  # the hip's other side is a leg: not judged
    assert warnings[0].startswith(f"{path}:6:26: warning: joint 'tail' holds 'hips' in the "
                                  "world by turning against 'tail'")
    assert "touches nothing in the start pose: 'tail' will turn instead" in warnings[0]
    assert main(["play", str(path), "--headless", "--seconds", "0.01"]) == 0
    assert warnings[0] in capsys.readouterr().err  # play says it too


def test_no_shipped_interface_gets_a_hold_warning():
    from pathlib import Path

    from puppet.data.yamlfile import load_file
    from puppet.physics.holds import frame_holds, hold_warnings

    root = Path(__file__).resolve().parents[1] / "interfaces"
    holds = 0
    for path in sorted(root.glob("*.yaml")):
        setup = load_setup(path.stem)
        holds += len(list(frame_holds(setup.interface)))
        assert hold_warnings(setup.interface, setup.character, load_file(path)) == [], path
    assert holds > 100  # the walks, the get-ups, the handstand: holds carried by the floor
