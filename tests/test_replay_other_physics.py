"""``puppet replay --headless --check --solver-passes N --step S``: is a feat a knife
edge? The log replayed on other physics, judged by its own expectations, its end state
not compared (any setting changes the bits)."""

from __future__ import annotations

import pytest

from puppet.data.catalog import ROOT
from puppet.timeline.log import read_log
from puppet.timeline.other_physics import OtherPhysics, rescaled
from puppet.timeline.replay import SAME_END, replay

LOGS = ROOT / "assets" / "logs"


def _failed(name: str, physics: OtherPhysics) -> list[str]:
    result = replay(LOGS / f"{name}.jsonl", physics=physics)
    if physics:  # other physics: the end state is not compared
        assert all(o.expectation != SAME_END for o in result.outcomes)
    return [o.expectation for o in result.failed]


def test_the_replay_uses_the_solver_asked_for():
    """The kip holds on its own 40 passes, on 36 and on 20; on 15 its landing no longer
    stands (touching_at_end fails): the verdict rests on the replay's solver."""
    assert _failed("biped-kip", OtherPhysics()) == []
    assert _failed("biped-kip", OtherPhysics(iterations=36)) == []
    assert _failed("biped-kip", OtherPhysics(iterations=20)) == []
    assert any(f.startswith("touching_at_end")
               for f in _failed("biped-kip", OtherPhysics(iterations=15)))


def test_on_another_step_every_event_keeps_its_time():
    """A log on a 1/240 s step has each event (and its end) at the step nearest its
    recorded time, in the recorded order; a layout of held poses keeps its feat there
    (luxo-keys-sit-stand)."""
    log = read_log(LOGS / "luxo-keys-sit-stand.jsonl")
    coarse = rescaled(log, 1 / 240)
    assert coarse.header["dt"] == 1 / 240 and log.header["dt"] == 1 / 480
    assert [e.event for e in coarse.events] == [e.event for e in log.events]
    for old, new in zip(log.events, coarse.events, strict=True):
        assert abs(new.step / 240 - old.step / 480) <= 0.5 / 240
    assert coarse.end["end"] == round(log.end["end"] / 2)
    assert _failed("luxo-keys-sit-stand", OtherPhysics(iterations=36, dt=1 / 240)) == []


def test_the_command_says_what_it_changed_and_fails_a_knife_edge(capsys):
    from puppet.commands import main

    assert main(["replay", "--headless", "--check", "--solver-passes", "15",
                 "biped-kip"]) == 1
    out, err = capsys.readouterr()
    assert "on 15 solver passes: the expectations judged, the end state not compared" in err
    assert "FAIL touching_at_end" in out and SAME_END not in out
    assert OtherPhysics(iterations=36, dt=1 / 240).label() == \
        "36 solver passes, a 1/240 s step"


@pytest.mark.parametrize("argv, said", [
    (["--step", "1/7"], "'1/7' is not a simulation step from 1/2000 to 1/30 s"),
    (["--step", "fast"], "'fast' is not a simulation step"),
    (["--solver-passes", "0"], "'0' is not a number of solver passes from 1 to 200"),
    (["--solver-passes", "36", "--until-step", "10", "--headless"],
     "--until-step counts the log's steps"),
    (["--step", "1/240"], "--solver-passes and --step need --headless"),
    (["--step", "1/240", "--headless", "--video", "x.mp4"],
     "go with --check, --frames and --screenshot"),
])
def test_bad_settings_are_one_line_and_exit_2(capsys, argv, said):
    from puppet.commands import main

    try:
        code = main(["replay", *argv, "luxo-hop"])
    except SystemExit as exc:  # argparse's usage errors
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert said in err and "\n" not in err, err


def test_frames_show_the_run_on_the_other_step(tmp_path, capsys):
    """``--frames`` with ``--step``: the images of the replay on that step (a knife
    edge's fall is something to look at), as many a second as on the recorded step."""
    from puppet.commands import main

    assert main(["replay", "--headless", "--step", "1/240", "--frames", str(tmp_path),
                 "--fps", "2", "luxo-hop"]) == 0
    out, err = capsys.readouterr()
    assert "on a 1/240 s step" in err and "step 1080 " in out  # 4.5 s of 1/240 s steps
    assert len(list(tmp_path.glob("*.png"))) == 9  # 2 a second over 4.5 s, and the first
