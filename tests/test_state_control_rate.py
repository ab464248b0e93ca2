"""A state's own `control_rate`: while that state is active the control steps (sensor
conditions, frame targets, sensor maps, blends) come at its rate, in every machine;
elsewhere at the interface's. Played through Session.handle/advance, as the window
does; the period follows from the saved states, so a checkpoint restores it."""

from __future__ import annotations

import textwrap

import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.interface import events as ev
from puppet.session import Session

LAYOUT = """
name: t
description: a state polled every step between states polled at 60 Hz
character: luxo
maps:
  - {input: mouse.x, joint: knee, frame: world, to: [0, 60]}
poses:
  lean: {joints: {ankle: -30}}
keys:
  - {key: l, pose: lean}
states:
  slow:
    transitions:
      - {to: fast, when: {sensor: input.mouse.y, above: 0.7}}
  fast:
    control_rate: 480
    transitions:
      - {to: slow, when: {sensor: input.mouse.y, below: 0.3}}
"""


def session(tmp_path, text: str = LAYOUT) -> Session:
    path = tmp_path / "t.yaml"
    path.write_text(textwrap.dedent(text))
    return Session(load_setup(str(path)))


def entered_after(s: Session, step: int, y: float, state: str) -> int:
    """Move the mouse's y at ``step``; the step the machine enters ``state``."""
    s.advance(step - s.steps)
    s.handle(ev.mouse(0.5, y))
    while s.runtime.states["main"] != state and s.steps < step + 50:
        s.advance(1)
    assert s.runtime.states["main"] == state
    return s.runtime.machines["main"].entered


def test_conditions_are_tested_every_step_only_in_the_fast_state(tmp_path):
    s = session(tmp_path)
    assert entered_after(s, 3, 0.8, "fast") == 8  # slow: the next multiple of 8 (60 Hz)
    assert entered_after(s, 21, 0.2, "slow") == 21  # fast: at once
    assert entered_after(s, 35, 0.8, "fast") == 40  # slow again: back to 60 Hz
    assert entered_after(s, 43, 0.2, "slow") == 43


def test_frame_targets_are_re_solved_every_step_only_in_the_fast_state(tmp_path):
    s = session(tmp_path)
    s.handle(ev.mouse(0.5, 0.5))
    s.handle(ev.key("l"))
    s.handle(ev.key("l", down=False))  # the lamp leans: the knee's world target moves

    def changes(steps: int) -> list[int]:
        knee = s.character.servos["knee"]
        seen, last = [], knee.target
        for _ in range(steps):
            s.advance(1)
            if knee.target != last:
                seen.append(s.steps)
                last = knee.target
        return seen

    slow = changes(80)
    assert len(slow) > 5 and all((step - 1) % 8 == 0 for step in slow), slow
    s.handle(ev.mouse(0.5, 0.8))  # to the fast state at the next 60 Hz poll
    s.advance(8)
    assert s.runtime.states["main"] == "fast"
    fast = changes(40)
    assert len(fast) > 30 and any((step - 1) % 8 for step in fast), fast
    s.handle(ev.mouse(0.5, 0.2))  # back to slow at once
    s.advance(1)
    assert s.runtime.states["main"] == "slow"
    again = changes(80)
    assert len(again) > 5 and all((step - 1) % 8 == 0 for step in again), again


@pytest.mark.parametrize("checkpoint_at", [12, 45])  # in the fast state, in the slow one
def test_a_checkpoint_restores_the_period_of_its_state(tmp_path, checkpoint_at):
    from puppet.session.playback import play

    events = [(0, ev.mouse(0.5, 0.5)), (1, ev.key("l")), (2, ev.key("l", down=False)),
              (5, ev.mouse(0.5, 0.8)), (checkpoint_at, ev.key("c")),
              (37, ev.mouse(0.5, 0.2)), (70, ev.mouse(0.5, 0.8)), (93, ev.mouse(0.5, 0.2))]
    events.sort(key=lambda e: e[0])
    straight = session(tmp_path)
    play(straight, events, 160)
    assert straight.runtime.machines["main"].entered == 93  # fast: at once

    s = session(tmp_path)
    play(s, events, 120)
    s.handle(ev.action("restore"))
    assert s.steps == checkpoint_at
    assert s.runtime.period.every == (1 if checkpoint_at < 37 else 8)
    play(s, [e for e in events if e[0] > checkpoint_at], 160)
    assert s.runtime.machines["main"].entered == 93
    assert s.sim.state_hash() == straight.sim.state_hash()
    s.rewind_to(checkpoint_at + 3)  # re-played from a keyframe, then on: the same again
    play(s, [e for e in events if e[0] > checkpoint_at + 3], 160)
    assert s.sim.state_hash() == straight.sim.state_hash()


def test_without_state_rates_nothing_changes(tmp_path):
    s = session(tmp_path, LAYOUT.replace("    control_rate: 480\n", ""))
    assert not s.runtime.period.fast
    assert entered_after(s, 3, 0.8, "fast") == 8
    assert entered_after(s, 21, 0.2, "slow") == 24


@pytest.mark.parametrize("value, message", [
    ("0", "control_rate"),
    ("fast", "control_rate"),
    ("60", "a state's control_rate makes the control steps faster while it is active: "
           "60 is not above the interface's 60"),
    ("64", "a state's control_rate makes the control steps faster while it is active: "
           "at 1/480 s 64 a second is one in 8 steps, as the interface's 60"),
])
def test_a_bad_state_rate_is_one_line_at_the_field(tmp_path, value, message):
    path = tmp_path / "t.yaml"
    text = textwrap.dedent(LAYOUT).replace("control_rate: 480", f"control_rate: {value}")
    path.write_text(text)
    with pytest.raises(DataError) as info:
        check_file(path)
    said = str(info.value)
    assert message in said and "\n" not in said, said
    line = text.split("\n").index(f"    control_rate: {value}") + 1
    assert said.startswith(f"{path}:{line}:"), said


MOUSE_ONLY = """
name: t
description: states that wait for the mouse, with timers, and one that reads the lamp
character: luxo
control_rate: 120
states:
  down:
    control_rate: 480
    enter: {set: {knee: 100}}
    transitions:
      - {to: up, when: {sensor: input.mouse.y, above: 0.6}}
      - {to: rest, after: 0.05}
  up:
    enter: {set: {knee: 20}}
    transitions:
      - {to: down, when: [{sensor: input.mouse.y, below: 0.4}, {sensor: input.mouse.x, above: 0.2}]}
  rest:
    transitions:
      - {to: down, when: {sensor: input.mouse.y, below: 0.3}, after: 0.05}
      - {to: up, when: {sensor: joint.knee, above: 150}}
"""


DEVICES = """
name: t
description: states that wait for the gamepad and the mouse's buttons
character: luxo
control_rate: 120
states:
  down:
    control_rate: 480
    enter: {set: {knee: 100}}
    transitions:
      - {to: up, when: {sensor: input.gamepad.a, above: 0.5}}
      - {to: rest, after: 0.3}
  up:
    enter: {set: {knee: 20}}
    transitions:
      - to: down
        when: [{sensor: input.mouse.left, above: 0.5}, {sensor: input.gamepad.left_x, above: 0.2}]
      - {to: rest, when: {sensor: input.gamepad.left_x, below: -0.5}}
  rest:
    transitions:
      - {to: down, when: {sensor: input.mouse.left, below: 0.5}, after: 0.05}
      - {to: up, when: {sensor: joint.knee, above: 150}}
"""


def _device_event(rng):
    """A gamepad stick or button, a mouse button or a mouse move."""
    kind = rng.choice(["stick", "button", "mouse_button", "mouse"])
    if kind == "stick":
        return ev.gamepad("left_x", rng.uniform(-1.0, 1.0))
    if kind == "button":
        return ev.gamepad("a", float(rng.random() < 0.5))
    if kind == "mouse_button":
        return ev.mouse_button("left", rng.random() < 0.5)
    return ev.mouse(rng.random(), rng.random())


def _run(tmp_path, quiet: bool, layout: str = MOUSE_ONLY,
         devices: bool = False, loop: bool = False) -> tuple[list, str, int]:
    """A wandering mouse (``devices``: and gamepad and mouse-button events), events at
    irregular steps; the states entered (with their steps), the end state and how many
    ticks ran (Python's: ``loop`` lets the kernel's stepping loop do them between, as
    it does where there is a kernel, ``interface.poll_plan``)."""
    import random

    s = session(tmp_path, layout)
    if not loop:
        s.runtime.poll = None
    if not quiet:  # poll every control step, as before
        for m in s.runtime.machines.values():
            m._device_only = dict.fromkeys(m._device_only, False)
            m.device_only = False
        s.runtime._device_machines = ()
    ticks = []
    tick = s.runtime.tick
    s.runtime.tick = lambda step: (ticks.append(step), tick(step))
    rng = random.Random(4)
    seen = []
    for _ in range(120):
        s.handle(_device_event(rng) if devices else ev.mouse(rng.random(), rng.random()))
        for _ in range(rng.choice([1, 2, 3, 7, 13, 40, 90])):
            s.advance(1)
            m = s.runtime.machines["main"]
            if not seen or seen[-1] != (m.current, m.entered):
                seen.append((m.current, m.entered))
    return seen, s.sim.state_hash(), len(ticks)


def test_a_state_reading_the_mouse_alone_polls_only_after_mouse_events(tmp_path):
    """The same states at the same steps as testing at every control step, with far
    fewer ticks."""
    quiet, end, ticks = _run(tmp_path, quiet=True)
    every, end_every, ticks_every = _run(tmp_path, quiet=False)
    assert len(quiet) > 30 and {s for s, _ in quiet} == {"down", "up", "rest"}
    assert quiet == every and end == end_every
    assert ticks < ticks_every / 2, (ticks, ticks_every)
    for polled in (True, False):  # the kernel's loop: the same states, steps and bits
        assert _run(tmp_path, quiet=polled, loop=True)[:2] == (quiet, end)


def test_a_quiet_state_polls_again_after_gamepad_and_mouse_button_events(tmp_path):
    """A key, a gamepad input, a mouse button or a channel stirs a quiet state as a
    mouse move does: the same states at the same steps as polling every control step."""
    quiet, end, ticks = _run(tmp_path, True, DEVICES, devices=True)
    every, end_every, ticks_every = _run(tmp_path, False, DEVICES, devices=True)
    assert len(quiet) > 30 and {s for s, _ in quiet} == {"down", "up", "rest"}
    assert quiet == every and end == end_every
    assert ticks < ticks_every, (ticks, ticks_every)
    for polled in (True, False):  # the kernel's loop: the same states, steps and bits
        assert _run(tmp_path, polled, DEVICES, devices=True, loop=True)[:2] == (quiet, end)


def test_a_quiet_state_still_sees_a_mouse_move_after_a_checkpoint(tmp_path):
    """The checkpoint (and a rewind) lands in `up`, a state that polls the mouse alone
    and has polled it: quiet. Restored, it still sees the next mouse moves."""
    from puppet.session.playback import play

    events = [(0, ev.mouse(0.5, 0.5)), (10, ev.mouse(0.5, 0.7)), (30, ev.key("c")),
              (50, ev.mouse(0.5, 0.9)), (81, ev.mouse(0.5, 0.1))]
    straight = session(tmp_path, MOUSE_ONLY)
    play(straight, events[:2], 30)
    machine = straight.runtime.machines["main"]
    assert machine.current == "up" and machine.entered == 10  # at 480: the event's step
    assert machine.quiet  # polled the mouse once: nothing more until the next event
    play(straight, events[2:], 100)
    assert straight.runtime.states["main"] == "down"
    assert machine.entered == 84  # `up` at 120: the next multiple of 4
    end = straight.sim.state_hash()

    s = session(tmp_path, MOUSE_ONLY)
    play(s, events, 100)
    s.handle(ev.action("restore"))
    assert s.steps == 30 and s.runtime.states["main"] == "up"
    play(s, [e for e in events if e[0] > 30], 100)
    assert s.runtime.machines["main"].entered == 84
    assert s.sim.state_hash() == end
    for at in (31, 45):  # rewound into the quiet state: re-played from a keyframe
        s.rewind_to(at)
        assert s.runtime.states["main"] == "up"
        play(s, [e for e in events if e[0] > at], 100)
        assert s.runtime.machines["main"].entered == 84
        assert s.sim.state_hash() == end


def test_a_reload_in_the_fast_state_keeps_its_period(tmp_path):
    """A hot reload while a state with its own rate is active: the new runtime takes
    the state over and polls at its rate, so the state is left on the event's step."""
    s = session(tmp_path)
    assert entered_after(s, 3, 0.8, "fast") == 8
    s.advance(12 - s.steps)
    s.handle(ev.reload(textwrap.dedent(LAYOUT).replace("description: a", "description: the")))
    assert "the state polled" in s.runtime.spec.description  # the new runtime
    assert s.runtime.states["main"] == "fast" and s.runtime.period.every == 1
    assert entered_after(s, 21, 0.2, "slow") == 21  # at once, not at 24
