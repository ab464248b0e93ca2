"""The same scripted input ends in the same bits, in this process and in others."""

import subprocess
import sys

from puppet.data.catalog import find, load_setup
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.script import compile_script, load_script


def _hash_in_process() -> str:
    spec = load_script(find("script", "luxo-hop"))
    session = Session(load_setup("luxo-mouse"))
    play(session, compile_script(spec, session.sim.dt), round(spec.seconds / session.sim.dt))
    return session.sim.state_hash()


def _hash_in_subprocess() -> str:
    out = subprocess.run([sys.executable, "-m", "puppet", "play", "luxo-mouse", "--headless",
                          "--input", "luxo-hop"], capture_output=True, text=True, check=True)
    return out.stdout.split("state=")[1].split()[0]


def test_two_separate_processes_end_in_bit_identical_state():
    first, second = _hash_in_subprocess(), _hash_in_subprocess()
    assert first == second
    assert first == _hash_in_process()


def test_hash_covers_positions_angles_and_velocities():
    session = Session(load_setup("luxo-mouse"))
    session.advance(10)
    before = session.sim.state_hash()
    body = session.character.bodies["upper_arm"]
    body.angular_velocity += 1e-12
    assert session.sim.state_hash() != before


def test_restoring_a_checkpoint_replays_bit_identically():
    spec = load_script(find("script", "luxo-hop"))
    events = compile_script(spec, 1 / 480)
    session = Session(load_setup("luxo-mouse"))
    play(session, events, 400)
    snap = session.sim.checkpoint()
    runtime_state = session.runtime.get_state()
    play(session, [e for e in events if e[0] >= 400], 1500)
    straight = session.sim.state_hash()
    session.sim.restore(snap)
    session.runtime.set_state(runtime_state)
    session.runtime.apply_maps()
    play(session, [e for e in events if e[0] >= 400], 1500)
    assert session.sim.state_hash() == straight
