"""A log replays on today's files unless asked for the run as recorded: the replay
command's ``--as-recorded`` and a ghost (which always shows the session as it was played)."""

from __future__ import annotations

from helpers import recorded_then_edited

from puppet.data.catalog import load_setup
from puppet.session import Session
from puppet.timeline.log import read_log


def test_a_ghost_plays_the_session_as_played_not_todays_interface(tmp_path):
    from puppet.timeline.ghost import Ghost

    _, log = recorded_then_edited(tmp_path)
    ghost = Ghost(log)
    assert ghost.setup.interface.maps[0].to == (60, -60)  # the recorded copy
    live = Session(load_setup("luxo-mouse"))
    live.advance(480)
    ghost.sync(live)
    assert ghost.session.sim.state_hash() == read_log(log).end_hash


def test_the_replay_command_replays_todays_interface_unless_asked_for_the_recorded(tmp_path):
    from puppet.timeline.report import replay_one

    _, log = recorded_then_edited(tmp_path)
    today = replay_one(str(log), None, False, False)
    recorded = replay_one(str(log), None, False, False, as_recorded=True)
    assert today["same_end"] is False and any("differs from the one recorded" in w
                                            for w in today["warnings"])
    assert recorded["same_end"] is True
