"""Checkpoints, keyframes and rewind, branching, blow-up recovery - and that logs of all
of them replay to the same end."""

import random

import pytest

from puppet.data.catalog import find, load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.history import History, Scrubber
from puppet.session.playback import play
from puppet.timeline.log import Recorder
from puppet.timeline.replay import LogFeeder, new_session, read_log, replay
from puppet.timeline.script import compile_script, load_script


def _hop_events(dt):
    return compile_script(load_script(find("script", "luxo-hop")), dt)


def _session(**kw):
    return Session(load_setup("luxo-mouse"), **kw)


def rewind(step):
    return {"type": "action", "name": "rewind", "to_step": step}


def test_restore_manual_checkpoint_then_same_inputs_is_bit_identical():
    events = _hop_events(1 / 480)
    session = _session()
    play(session, [e for e in events if e[0] < 530], 530)  # mid-motion, between boundaries
    session.handle(ev.action("checkpoint"))
    later = [e for e in events if e[0] >= 530]
    play(session, later, 1600)
    straight = session.sim.state_hash()  # never restored
    for _ in range(2):
        session.handle(ev.action("restore"))
        assert session.steps == 530
        play(session, later, 1600)
        assert session.sim.state_hash() == straight


@pytest.mark.parametrize("setup,script", [("luxo-mouse", "luxo-hop"),
                                          ("cat-bound", "cat-bound")])
def test_rewind_shows_exactly_what_was_played(setup, script):
    """Automatic checkpoints re-seat the run like manual ones: rewinding to any step,
    across ground contacts and several keyframes, gives the very bits that were there."""
    session = Session(load_setup(setup), checkpoint_interval=1.0)
    events = compile_script(load_script(find("script", script)), session.sim.dt)
    seen = {}
    per = round(1.0 / session.sim.dt)  # steps a second: the character's (the cat's 240)
    steps = round(2000 * per / 480)  # 4.17 s
    sample_every = round(173 * per / 480)  # not a multiple of the keyframe interval

    def sample(s):
        seen[s.steps] = s.sim.state_hash()

    play(session, events, steps, sample_every, sample)
    assert [s.step for s in session.history.auto] == [0, per, 2 * per, 3 * per, 4 * per]
    for step in sorted(seen, reverse=True):
        session.rewind_to(step)
        assert session.sim.state_hash() == seen[step], step
    assert len(seen) == steps // sample_every


def test_result_does_not_depend_on_how_advance_is_split():
    events = [e for e in _hop_events(1 / 480) if e[0] < 1500]
    a, b = _session(), _session()
    play(a, events, 1500)
    rng = random.Random(1)
    pending = list(events)
    while a.steps != b.steps or pending:
        while pending and pending[0][0] <= b.steps:
            b.handle(pending.pop(0)[1])
        target = pending[0][0] if pending else 1500
        b.advance(min(rng.randint(1, 13), target - b.steps))
    assert a.sim.state_hash() == b.sim.state_hash()


def test_rewind_restores_state_and_runtime_inputs():
    session = _session()
    session.handle(ev.mouse(0.9, 0.2))
    session.advance(480)
    snap_state = session.sim.state_hash()
    inputs = dict(session.runtime.inputs)
    session.handle(ev.mouse(0.1, 0.9))
    session.advance(240)
    assert session.runtime.inputs != inputs
    session.handle(rewind(480))
    assert session.steps == 480 and session.sim.state_hash() == snap_state
    assert session.runtime.inputs == inputs
    with pytest.raises(ValueError, match="no snapshot"):
        session.handle(rewind(721))  # beyond the history


def test_rewind_to_any_step_rebuilds_it_from_keyframe_and_input():
    """Between keyframes a rewind re-simulates the recorded input: the state shown is
    the one the player saw, to within the solver's warm start (sub-millimetre)."""
    events = _hop_events(1 / 480)
    session = _session()
    seen = {}
    play(session, [e for e in events if e[0] < 1700], 1700, every=100,
         on_tick=lambda s: seen.setdefault(s.steps, s.sim.state_vector()))
    for step in (1000, 1100, 1200):  # mid-hop, between the keyframes at 960 and 1440
        session.handle(rewind(step))
        assert session.steps == step
        now = session.sim.state_vector()
        assert max(abs(a - b) for a, b in zip(now[::6], seen[step][::6])) < 1e-3
    # The same rewinds in another session give the same bits (replays are exact).
    other = _session()
    play(other, [e for e in events if e[0] < 1700], 1700)
    other.handle(rewind(1200))
    assert other.sim.state_hash() == session.sim.state_hash()


def test_new_input_after_rewind_branches_the_history():
    session = _session()
    session.advance(960)
    assert session.history.span() == (0, 960)
    session.handle(rewind(480))
    assert session.history.span() == (0, 960)  # still there to scrub forward to
    session.handle(ev.mouse(0.3, 0.3))
    assert session.history.span() == (0, 480)
    session.advance(100)
    assert session.history.span() == (0, 580)


def test_stepping_on_after_a_rewind_also_branches():
    session = _session()
    session.advance(960)
    session.handle(rewind(480))
    session.advance(1)
    assert session.history.span() == (0, 481)


def test_keyframes_are_bounded():
    h = History(0.01, checkpoint_interval=1.0, keep_seconds=2.0)
    session = _session(dt=0.01)
    h.set_start(session.history.start)
    session.history = h
    session.advance(1000)  # 10 s
    assert [s.step for s in h.auto] == [800, 900, 1000]
    assert h.span() == (800, 1000)


def test_restore_goes_to_the_last_manual_checkpoint_else_automatic():
    session = _session(checkpoint_interval=1.0)
    session.advance(700)
    session.handle(ev.action("restore"))  # no manual one: the automatic one at 1 s
    assert session.steps == 480
    session.advance(100)
    session.handle(ev.key("c", True))  # the checkpoint key
    session.handle(ev.key("c", False))
    session.advance(1000)
    session.handle(ev.key("backspace", True))
    assert session.steps == 580
    assert session.history.checkpoint_steps() == [580]


def test_blow_up_restores_last_good_checkpoint_and_says_so():
    session = _session()
    session.advance(500)
    session.character.bodies["upper_arm"].velocity = (1e6, 0)
    session.advance(300)  # must not raise; the health check comes every 0.5 s
    assert not session.sim.blown_up()
    assert session.blowups == 1 and "blew up" in session.message
    assert session.steps == 800  # time goes on
    session.advance(500)
    assert not session.sim.blown_up()


def _record_interactive(path, frames_seed=3):
    """A 'window' session: odd frame sizes, mouse moves, a checkpoint, a scrub back,
    a new branch, a restore and a reset, recorded."""
    session = _session()
    rng = random.Random(frames_seed)
    rec = Recorder(session, path)
    scrub = Scrubber(session)
    for frame in range(400):
        if frame % 7 == 0:
            session.handle(ev.mouse(rng.random(), rng.random()))
        if frame == 60:
            session.handle(ev.key("c", True))
        if 150 <= frame < 190:  # hold the rewind key for 40 frames
            if frame == 150:
                assert session.handle(ev.key("b", True)) == "rewind"
                scrub.start()
            scrub.update(1 / 60)
            continue
        if frame == 190:
            scrub.release()
            session.handle(ev.key("b", False))
        if frame == 300:
            session.handle(ev.key("backspace", True))
        if frame == 350:
            session.handle(ev.key("r", True))
        session.advance(rng.randint(5, 11))
    rec.close()
    return session


def test_log_with_rewind_checkpoint_restore_replays_to_the_same_end(tmp_path):
    path = tmp_path / "live.jsonl"
    live = _record_interactive(path)
    log = read_log(path)
    steps = [e.step for e in log.events]
    assert any(b < a for a, b in zip(steps, steps[1:])), "the rewind should make steps go back"
    assert any(e.event.get("name") == "rewind" for e in log.events)
    result = replay(path)
    assert result.final_hash == live.sim.state_hash() == log.end_hash
    assert result.ok, [str(o) for o in result.failed]


def test_the_viewers_replay_feeder_matches_headless_replay(tmp_path):
    path = tmp_path / "live.jsonl"
    live = _record_interactive(path)
    log = read_log(path)
    session = new_session(log, load_setup("luxo-mouse"))
    feeder = LogFeeder(session, log)
    rng = random.Random(9)
    while not feeder.finished:
        feeder.advance(rng.randint(1, 20))
    assert session.steps == log.end_step
    assert session.sim.state_hash() == live.sim.state_hash()


def test_scrubbing_back_and_forward():
    session = _session()
    session.advance(2400)  # 5 s
    scrub = Scrubber(session)
    scrub.start()
    frames = 0
    while session.steps == 2400 and frames < 10:  # the preview's cache fills in slices
        scrub.update(1 / 60)
        frames += 1
    assert 2300 < session.steps < 2400  # the first frames back show within a few frames
    for _ in range(60):
        scrub.update(1 / 60)
    back = session.steps
    assert back < 2380 - 200
    for _ in range(10):
        scrub.update(1 / 60, forward=True)
    assert back < session.steps <= 2400
    listened = []
    session.listener = lambda step, e: listened.append((step, e))
    shown = session.steps
    scrub.release()
    # logged at the step the run was at (a replay plays on to there, then rewinds)
    assert listened == [(2400, rewind(shown))] and session.steps == shown


def test_a_checkpoint_interval_of_zero_means_the_default():
    from puppet.session.history import CHECKPOINT_EVERY, History

    dt = 1 / 480
    assert History(dt, 0).checkpoint_every == History(dt, CHECKPOINT_EVERY).checkpoint_every
    assert History(dt, 0).checkpoint_every > 1
