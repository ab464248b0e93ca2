"""A sequence step that ends on a sensor (``until``, docs/interfaces/04-sequences.md):
``hold`` becomes the longest wait, ``after`` the shortest, the condition is the same
syntax as a transition's ``when`` and is tested every simulation step; a checkpoint
taken in such a step restores exactly (issue 28: moves that do not depend on the step).
"""

import math
import pickle
import textwrap

import pytest

from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session

HEADER = "name: t\ndescription: test interface\ncharacter: luxo\n"
# A hop whose push lasts until the base is 3 cm up (at most 0.2 s), whose tuck lasts
# until the base is down again (from 0.1 s in, at most 1 s), then a stand.
HOP = """
poses:
  crouch: {joints: {ankle: -80, knee: 125}}
  push: {joints: {ankle: -20, knee: 140}, stiffness: {ankle: 60, knee: 40}}
  tuck: {joints: {ankle: -30, knee: 75}}
  stand: {joints: {ankle: -25, knee: 55}}
sequences:
  hop:
    - {pose: crouch, hold: 0.5}
    - {pose: push, hold: 0.2, until: {sensor: height.base, above: 0.055}}
    - {pose: tuck, hold: 1.0, after: 0.1, until: {sensor: contact.base, is: true}}
    - {pose: stand, hold: 0.4}
  never: [{pose: crouch, hold: 0.3, until: [{sensor: contact.base, is: true},
                                            {sensor: root.angle, above: 170}]},
          {pose: stand, hold: 0.1}]
  late: [{pose: crouch, hold: 0.3, after: 0.2, until: {sensor: contact.base, is: true}},
         {pose: stand, hold: 0.1}]
keys:
  - {key: h, sequence: hop}
  - {key: n, sequence: never}
  - {key: l, sequence: late}
states:  # a machine polled at the control rate: the runtime ticks between the steps' ends
  up:
    transitions: [{to: over, when: {sensor: root.angle, above: 170}}]
  over: {}
"""


def make(tmp_path, text: str = HOP, dt: float = 1 / 480) -> Session:
    path = tmp_path / "iface.yaml"
    path.write_text(HEADER + textwrap.dedent(text))
    return Session(load_setup(str(path)), dt=dt)


def press(session, key):
    session.handle(ev.key(key, True))
    session.handle(ev.key(key, False))


def base_height(s) -> float:
    return s.character.link_position("base")[1]


def index(s):
    seq = s.runtime.sequence
    return None if seq is None else seq.index


def run_until_index(s, i, limit=2000) -> int:
    for n in range(limit):
        if index(s) == i:
            return n
        s.advance(1)
    raise AssertionError(f"step {i} never began")


@pytest.mark.parametrize("dt", [1 / 480, 1 / 240])
def test_the_push_ends_the_step_after_the_base_rises_past_the_line(tmp_path, dt):
    s = make(tmp_path, dt=dt)
    s.advance(round(1.0 / dt))  # settled
    press(s, "h")
    run_until_index(s, 1)
    heights = []
    while index(s) == 1:
        heights.append(base_height(s))
        s.advance(1)
    # the step ended at the first step the condition held (tested at each step, before
    # stepping from it): the last height seen in it is the first past the line
    assert all(h <= 0.055 for h in heights[:-1]) and heights[-1] > 0.055
    assert len(heights) < round(0.2 / dt)  # well before the hold's 0.2 s


def test_the_tuck_waits_for_touch_down_after_its_after(tmp_path):
    s = make(tmp_path)
    s.advance(480)
    press(s, "h")
    run_until_index(s, 2)
    began = s.steps
    run_until_index(s, 3)
    assert s.steps - began >= 48  # not before 'after' (0.1 s)
    assert s.character.in_contact("base")  # it ended on touch-down ...
    assert s.steps - began < 480  # ... before the 1 s hold


def test_hold_is_the_longest_wait_when_the_condition_never_holds(tmp_path):
    s = make(tmp_path)
    s.advance(480)
    press(s, "n")  # upside down on the floor: never
    start = s.steps
    run_until_index(s, 1)
    assert s.steps - start == round(0.3 * 480) + 1  # the hold, as without 'until'


def test_after_keeps_the_condition_from_ending_the_step_earlier(tmp_path):
    s = make(tmp_path)
    s.advance(480)
    press(s, "l")  # on the floor all along: ends as soon as 'after' has passed
    start = s.steps
    run_until_index(s, 1)
    assert s.steps - start == round(0.2 * 480) + 1


@pytest.mark.parametrize("key, i", [("h", 2), ("l", 0)])
def test_a_checkpoint_in_an_until_step_restores_exactly(tmp_path, key, i):
    s = make(tmp_path)
    s.advance(480)
    press(s, key)
    run_until_index(s, i)
    s.advance(20)  # in the step, 'after' not over yet: when the step began is kept
    assert index(s) == i
    snap = s.sim.checkpoint()
    state = pickle.loads(pickle.dumps(s.runtime.get_state()))
    s.advance(600)
    straight = (s.sim.state_hash(), index(s),
                {n: math.degrees(v.target) for n, v in s.character.servos.items()})
    s.sim.restore(snap)
    s.runtime.set_state(state)
    s.advance(600)
    assert (s.sim.state_hash(), index(s),
            {n: math.degrees(v.target) for n, v in s.character.servos.items()}) == straight


@pytest.mark.parametrize("step, message", [
    ("{pose: crouch, hold: 0.3, after: 0.1}", "needs 'until'"),
    ("{pose: crouch, hold: 0.3, after: 0.3, until: {sensor: contact.base, is: true}}",
     "less than 'hold'"),
    ("{pose: crouch, hold: 0.3, until: []}", "empty list"),
    ("{pose: crouch, hold: 0.3, until: {sensor: height.bse, above: 0.1}}", "bse"),
])
def test_bad_until_steps_are_load_errors(tmp_path, step, message):
    text = f"""
    poses:
      crouch: {{joints: {{ankle: -80, knee: 125}}}}
    sequences:
      s: [{step}]
    keys:
      - {{key: s, sequence: s}}
    """
    with pytest.raises(DataError, match=message):
        make(tmp_path, text)
