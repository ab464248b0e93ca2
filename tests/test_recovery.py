"""Blow-ups and leaving the world are caught within a frame; recovery goes back to
earlier checkpoints, then the start, then halts with one message: it never loops.
Headless runs report each and exit 3."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session, world_box
from puppet.session.playback import play
from puppet.timeline.replay import replay

ROOT = Path(__file__).resolve().parents[1]
# A short floor whose gravity pulls sideways: every state, the start included, slides
# off its end, so no checkpoint can save the run.
TILTED = """\
name: tilted
description: a 3 m floor with gravity pulling toward its end
gravity: [30.0, -9.81]
ground:
  - points: [[-1.0, 0.0], [2.0, 0.0]]
    friction: 0.9
"""
IFACE = (ROOT / "interfaces" / "luxo-mouse.yaml").read_text().replace("scene: flat",
                                                                      "scene: tilted")


def _tilted(tmp_path) -> Path:
    (tmp_path / "tilted.yaml").write_text(TILTED)
    iface = tmp_path / "iface.yaml"
    iface.write_text(IFACE)
    return iface


def test_leaving_the_world_is_caught_within_a_frame():
    session = Session(load_setup("luxo-mouse"))
    session.advance(1440 + 100)  # past the checkpoint at 3 s
    x0, x1, y0, _ = world_box(session.setup.scene)
    for body in session.character.bodies.values():  # carried past the floor's end
        body.position = (x1 + 0.5, body.position.y)
    session.advance(8)  # one frame (1/60 s)
    assert session.blowups == 1, session.message
    assert re.fullmatch(r"the simulation left the world at t=3\.22 s; restored the "
                        r"checkpoint of t=3\.00 s", session.message), session.message
    assert x0 < session.character.bodies["base"].position.x < x1
    session.advance(2000)
    assert session.blowups == 1 and session.halted is None


def test_a_nan_is_caught_within_a_frame():
    session = Session(load_setup("luxo-mouse"))
    session.advance(300)
    session.character.bodies["base"].velocity = (float("nan"), 0.0)
    session.advance(8)
    assert session.blowups == 1 and "blew up at t=0.63 s" in session.message


def test_a_doomed_run_goes_back_step_by_step_then_halts_once(tmp_path):
    session = Session(load_setup(str(_tilted(tmp_path))))
    for _ in range(60 * 60):  # a minute of frames
        session.handle(ev.mouse(0.5, 0.5))
        session.advance(8)
    notes = session.blowup_messages
    assert session.halted is not None and notes[-1] == session.halted
    assert "again after going back to the start; stopped" in session.halted
    restored = [float(m.group(1)) for n in notes
                if (m := re.search(r"restored the checkpoint of t=([\d.]+) s", n))]
    assert restored and restored[-1] == 0.0, notes  # the last try is the start
    assert restored == sorted(restored, reverse=True)[:len(restored)] or len(restored) < 3
    assert len(notes) <= 6, notes  # a few tries, never a loop
    assert session.steps == 60 * 60 * 8  # time goes on; the physics stands still
    frozen = session.sim.state_hash()
    session.advance(480)
    assert session.sim.state_hash() == frozen and len(session.blowup_messages) == len(notes)
    session.handle(ev.action("reset"))  # a reset starts the physics again
    assert session.halted is None
    session.advance(8)
    assert session.sim.state_hash() != frozen


def test_a_doomed_headless_run_exits_3_and_its_log_replays_the_same(tmp_path):
    iface = _tilted(tmp_path)
    log = tmp_path / "doomed.jsonl"
    proc = subprocess.run([sys.executable, "-m", "puppet", "play", str(iface), "--headless",
                           "--seconds", "20", "--record", str(log)],
                          capture_output=True, text=True)
    assert proc.returncode == 3, proc.stderr
    lines = proc.stderr.splitlines()
    assert lines and all(line.startswith("puppet play: the simulation ") for line in lines)
    assert "stopped" in lines[-1] and len(lines) <= 6
    state = re.search(r"state=(\w+)", proc.stdout).group(1)
    result = replay(log)
    assert result.final_hash == state and result.same_end
    assert [f"puppet play: {b}" for b in result.blowups] == lines
    proc = subprocess.run([sys.executable, "-m", "puppet", "replay", str(log), "--headless"],
                          capture_output=True, text=True)
    assert proc.returncode == 3 and "(same as recorded)" in proc.stdout, proc.stderr


def test_recovery_is_the_same_after_a_rewind_across_it(tmp_path):
    session = Session(load_setup(str(_tilted(tmp_path))))
    play(session, [(0, ev.mouse(0.5, 0.5))], 480 * 12)
    notes, end = list(session.blowup_messages), session.sim.state_hash()
    assert notes
    session.rewind_to(480)
    session.rewind_to(480 * 12)  # re-simulates the recoveries: none is new
    assert session.blowup_messages == notes and session.sim.state_hash() == end


@pytest.mark.parametrize("linear, angular", [(250.0, 0.0), (0.0, 2.0e4), (150.0, 5000.0)])
def test_a_runaway_linear_or_angular_speed_alone_is_a_blow_up(linear, angular):
    from puppet.physics.simulation import MAX_SPEED

    s = Session(load_setup("luxo-mouse"))
    assert not s.sim.blown_up()
    body = s.character.bodies["upper_arm"]
    body.velocity = (linear, 0.0)
    body.angular_velocity = angular
    runaway = linear > MAX_SPEED or angular > 50 * MAX_SPEED
    assert s.sim.blown_up() is runaway


@pytest.mark.parametrize("vy", [250.0, -250.0])
def test_a_runaway_vertical_speed_alone_is_a_blow_up(vy):
    s = Session(load_setup("luxo-mouse"))
    s.character.bodies["upper_arm"].velocity = (0.0, vy)
    assert s.sim.blown_up()
