"""A transition's `for` asks that its `when` (one condition, or a list that must all
hold at once) has held that long without a break: a flickering contact is not a
take-off. Played through Session.handle/advance, as the window does."""

from __future__ import annotations

import textwrap

import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session

CORNER = """
name: t
description: both mouse axes as one transition's conditions, and a held one
character: luxo
control_rate: 120
states:
  waiting:
    transitions:
      - {to: corner, when: [{sensor: input.mouse.x, above: 0.7},
                            {sensor: input.mouse.y, above: 0.7}]}
      - {to: held, when: {sensor: input.mouse.x, below: 0.3}, for: 0.25}
  corner:
    transitions: [{to: waiting, after: 0.05}]
  held: {}
"""


def session(tmp_path, text: str) -> Session:
    path = tmp_path / "t.yaml"
    path.write_text(textwrap.dedent(text))
    return Session(load_setup(str(path)))


def test_a_list_of_conditions_fires_only_when_all_of_them_hold(tmp_path):
    s = session(tmp_path, CORNER)
    seen = []
    for x, y in ((0.8, 0.5), (0.5, 0.8), (0.8, 0.8)):
        s.handle(ev.mouse(x, y))
        s.advance(8)  # two polls at 120 Hz
        seen.append(s.runtime.states["main"])
    assert seen == ["waiting", "waiting", "corner"]


def test_for_waits_until_the_condition_has_held_that_long_without_a_break(tmp_path):
    s = session(tmp_path, CORNER)
    s.handle(ev.mouse(0.2, 0.5))  # x below 0.3 from step 0
    s.advance(100)  # 0.21 s: not yet
    s.handle(ev.mouse(0.5, 0.5))  # a break: the clock starts again
    s.advance(4)
    s.handle(ev.mouse(0.2, 0.5))
    start = s.steps
    states = []
    while s.runtime.states["main"] == "waiting" and s.steps < start + 400:
        s.advance(1)
        states.append(s.steps)
    assert s.runtime.states["main"] == "held"
    # it fired 0.25 s (120 steps) after the condition held again, to the control period
    assert 120 <= s.runtime.machines["main"].entered - start <= 124


def test_a_checkpoint_taken_while_a_for_condition_holds_replays_to_the_same_step(tmp_path):
    from puppet.session.playback import play

    events = [(0, ev.mouse(0.2, 0.5)), (60, ev.key("c")), (90, ev.mouse(0.2, 0.4))]
    straight = session(tmp_path, CORNER)
    play(straight, events, 200)
    entered = straight.runtime.machines["main"].entered
    assert straight.runtime.states["main"] == "held" and 120 <= entered <= 124

    s = session(tmp_path, CORNER)
    play(s, events, 100)
    s.handle(ev.action("restore"))  # back to step 60, the condition holding since 0
    assert s.steps == 60
    play(s, [e for e in events if e[0] > 60], 200)
    assert s.runtime.machines["main"].entered == entered
    assert s.sim.state_hash() == straight.sim.state_hash()


@pytest.mark.parametrize("transition, at, message", [
    ("{to: corner, after: 1, for: 0.1}", "0.1", "'for' (s) is how long 'when' must have held"),
    ("{to: corner, when: [{sensor: input.mouse.x, above: 0.7}, {sensor: lean, is: true}]}",
     "{sensor: lean", "'is' only applies to contact.LINK sensors"),
    ("{to: corner, when: [{sensor: input.mouse.x, above: 0.7}, {sensor: angle.shade, above: 1}]}",
     "angle.shade", "unknown link 'shade'"),
])
def test_errors_in_a_list_of_conditions_or_for_point_at_the_field(tmp_path, transition, at,
                                                                   message):
    """One line, at the line and column of what is wrong: the list, the value of `for`,
    the condition of the list that is wrong or its sensor."""
    path = tmp_path / "t.yaml"
    text = textwrap.dedent(CORNER).split("\n")
    text[8:10] = [f"      - {transition}"]
    path.write_text("\n".join(text))
    with pytest.raises(DataError) as info:
        check_file(path)
    said = str(info.value)
    assert message in said and "\n" not in said
    assert said.startswith(f"{path}:9:{text[8].index(at) + 1}: ")
