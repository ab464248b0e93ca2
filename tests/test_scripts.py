"""Scripted performances: a key held for its hold then released, a drag gliding at the
mouse rate, a push naming a link the character lacks refused at its line."""

from __future__ import annotations

import textwrap

import pytest

from puppet.data.errors import DataError
from puppet.interface import events as ev


def test_a_scripted_drag_glides_to_its_target_at_the_mouse_rate():
    from puppet.data.yamlfile import load_text
    from puppet.timeline.script import compile_script, parse_script

    spec = parse_script(load_text(textwrap.dedent("""\
        events:
          - {t: 0.5, drag: {link: base, start: [0.0, 0.2], to: [0.3, 0.5], over: 0.5, hold: 0.1}}
        """), "glide.yaml"))
    dt = 1 / 480
    events = compile_script(spec, dt)
    moves = [(step, e["target"]) for step, e in events if e.get("phase") == "move"]
    assert len(moves) == 120  # 0.5 s at 240 Hz
    assert moves[-1] == (480, pytest.approx([0.3, 0.5]))
    assert moves[59][1] == pytest.approx([0.15, 0.35])  # half way, half the way
    steps = [step for step, _ in moves]
    assert steps == sorted(steps) and steps[0] == 242
    assert events[0][0] == 240 and events[0][1]["phase"] == "start"
    assert events[-1] == (528, {"type": "drag", "phase": "end"})


def test_a_scripted_key_is_pressed_then_released_after_its_hold():
    from puppet.timeline.script import ScriptSpec, compile_script

    spec = ScriptSpec.model_validate({"events": [{"t": 1.0, "key": "a", "hold": 0.5}]})
    got = compile_script(spec, 1 / 480)
    assert got == [(480, ev.key("a", True)), (720, ev.key("a", False))]


def test_a_script_pushing_a_link_the_character_lacks_is_named_at_its_line(tmp_path):
    from puppet.timeline.script import check_links, load_script

    path = tmp_path / "s.yaml"
    path.write_text("events:\n  - {t: 0.5, push: {link: tail, impulse: [1, 0]}}\n")
    with pytest.raises(DataError) as info:
        check_links(path, load_script(path), ["base", "lower_arm", "upper_arm"])
    msg = str(info.value)
    assert msg.startswith(f"{path}:2:") and "tail" in msg and "\n" not in msg
