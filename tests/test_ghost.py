"""A ghost: a recorded log replaying beside the live run, in step with its simulated
time, forward and back (puppet.timeline.ghost)."""

from __future__ import annotations

from pathlib import Path

from puppet.data.catalog import load_setup
from puppet.session import Session


def test_a_ghost_plays_its_log_in_step_with_the_live_time_and_back():

    from puppet.timeline.ghost import Ghost
    from puppet.timeline.replay import replay

    hop = Path(__file__).resolve().parents[1] / "assets" / "logs" / "luxo-hop.jsonl"
    live = Session(load_setup("luxo-mouse"))  # standing still beside the ghost
    live.advance(600)
    ghost = Ghost(hop)
    ghost.sync(live)
    assert ghost.session.steps == 600
    assert ghost.session.sim.state_hash() == replay(hop, until_step=600).final_hash
    live.rewind_to(300)
    ghost.sync(live)
    assert ghost.session.steps == 300
    assert ghost.session.sim.state_hash() == replay(hop, until_step=300).final_hash
