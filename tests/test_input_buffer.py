"""Input buffering (``buffer:`` on a state's key): a press made a little before the
state that takes it acts when that state is entered, as fighting games keep a press
made during a move's last frames. Luxo, so that it is cheap; the walk's use of it is in
tests/test_biped_walk.py."""

from __future__ import annotations

import textwrap

import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session

STEPS = 480  # per simulated second

LAYOUT = """
name: t
description: x acts only in 'ready' (0.3 s after the start); a press 0.2 s early counts
character: luxo
states:
  busy:
    transitions: [{to: ready, after: 0.3}]
  ready:
    keys:
      - {key: x, goto: done, buffer: 0.2}
  done:
    enter: {set: {knee: 90}}
    transitions: [{to: busy, after: 0.5}]
"""


def session(tmp_path) -> Session:
    path = tmp_path / "t.yaml"
    path.write_text(textwrap.dedent(LAYOUT))
    return Session(load_setup(str(path)))


def press(s, key="x"):
    s.handle(ev.key(key, True))
    s.handle(ev.key(key, False))


def state_after(s, steps):
    s.advance(steps)
    return s.runtime.state


def test_a_press_shortly_before_the_state_acts_when_it_is_entered(tmp_path):
    s = session(tmp_path)
    s.advance(int(0.15 * STEPS))
    press(s)  # 0.15 s before 'ready': nothing binds x yet
    assert s.runtime.state == "busy"
    s.advance(int(0.15 * STEPS))
    assert s.runtime.state == "busy"  # 'ready' is entered by the tick at this step ...
    assert state_after(s, 1) == "done"  # ... and the press acts then
    assert s.runtime.machines["main"].entered == int(0.3 * STEPS)


def test_a_press_older_than_the_buffer_is_not_taken(tmp_path):
    s = session(tmp_path)
    s.advance(int(0.05 * STEPS))
    press(s)  # 0.25 s early: more than the key's 0.2 s
    assert state_after(s, int(0.3 * STEPS)) == "ready"
    press(s)  # pressed in the state: acts at once
    assert s.runtime.state == "done"


def test_a_later_press_replaces_an_earlier_one_and_a_press_acts_once(tmp_path):
    s = session(tmp_path)
    press(s)  # 0.3 s early: too old by itself
    s.advance(int(0.2 * STEPS))
    press(s)  # 0.1 s early: this one counts
    assert state_after(s, int(0.1 * STEPS) + 1) == "done"
    # done -> busy (0.5 s) -> ready (0.3 s): the spent press does not act again
    assert state_after(s, int(0.8 * STEPS) + 1) == "ready"


def test_a_press_that_acted_is_not_kept(tmp_path):
    s = session(tmp_path)
    s.advance(int(0.3 * STEPS) + 1)
    assert s.runtime.state == "ready"
    press(s)  # acts in 'ready'
    assert s.runtime.state == "done"
    s.advance(int(0.5 * STEPS))  # back to busy; 0.3 s later ready again, no new press
    assert state_after(s, int(0.3 * STEPS) + 1) == "ready"


def test_a_kept_press_rides_along_with_checkpoints(tmp_path):
    """Checkpoints (and so rewinds and replays) bring a kept press back with the rest of
    the runtime's state."""
    s = session(tmp_path)
    s.advance(int(0.2 * STEPS))
    press(s)
    s.checkpoint()
    assert state_after(s, int(0.1 * STEPS) + 1) == "done"
    s.restore_checkpoint()
    assert s.runtime.state == "busy" and s.runtime.buffer.unused == {"x": int(0.2 * STEPS)}
    assert state_after(s, int(0.1 * STEPS) + 1) == "done"


def test_a_reset_forgets_a_kept_press(tmp_path):
    s = session(tmp_path)
    s.advance(int(0.2 * STEPS))
    press(s)
    s.reset()
    assert s.runtime.buffer.unused == {}
    assert state_after(s, int(0.3 * STEPS) + 1) == "ready"


@pytest.mark.parametrize("other", ["y", "shift+x"])
def test_only_the_buffered_key_is_kept(tmp_path, other):
    s = session(tmp_path)
    press(s, other)
    assert s.runtime.buffer.unused == {}
