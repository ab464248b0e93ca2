"""A halted run says so on its end line, and a run that blows up again and again says it
once, with the count (issue 32)."""

from puppet.commands.play import blowup_exit, end_line
from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.blowups import fold


def _pushed(every: float, seconds: float) -> Session:
    """luxo-mouse shoved up hard every ``every`` s: a blow-up at each shove."""
    s = Session(load_setup("luxo-mouse"))
    dt = s.sim.dt
    events = [(round(k * every / dt), ev.push("base", (0.0, 500.0)))
              for k in range(1, int(seconds / every))]
    play(s, events, round(seconds / dt))
    return s


def test_a_halted_run_says_so_on_its_end_line(capsys):
    s = _pushed(2.0, 8.0)  # fails again after going back to the start: halted
    assert s.halted
    line = end_line(s)
    assert line.startswith("t=8.000s  halted at t=4.02 s after 2 blow-ups  state="), line
    assert "com=" not in line and "upright" not in line
    assert blowup_exit(s) == 3
    err = capsys.readouterr().err.splitlines()
    assert err[-1].startswith("puppet play: the simulation blew up at t=4.02 s again after "
                              "going back to the start; stopped"), err


def test_blow_ups_again_and_again_are_said_once_with_the_count(capsys):
    s = _pushed(7.0, 32.0)
    assert s.blowups >= 3 and not s.halted
    assert end_line(s).split("  ")[1].startswith("com=")  # not halted: where it is
    assert blowup_exit(s) == 3
    err = capsys.readouterr().err.splitlines()
    last = s.blowup_messages[-1].split("at t=")[1].split(" s;")[0]
    assert len(err) == 1 and err[0].startswith(
        f"puppet play: the simulation blew up {s.blowups} times (first at t=7.02 s, last "
        f"at t={last} s); restored the last checkpoint before it each time (t=6.00.."), err


def test_sixteen_returns_to_the_start_are_one_line():
    left = [f"the simulation left the world at t={1.5 + 2 * k:.2f} s; restored the checkpoint "
            f"of t=0.00 s" for k in range(16)]
    halt = ("the simulation left the world at t=40.00 s again after going back to the "
            "start; stopped (reset, rewind or change the interface)")
    blew = "the simulation blew up at t=20.00 s; restored the checkpoint of t=18.00 s"
    assert fold(left[:8] + [blew] + left[8:] + [halt]) == [
        "the simulation left the world 16 times (first at t=1.50 s, last at t=31.50 s); "
        "restored the checkpoint of t=0.00 s each time", blew, halt]
    assert fold(left[:1]) == left[:1] and fold([]) == []


def test_a_replay_folds_its_blow_ups_too(capsys):
    from puppet.timeline.report import print_notes

    notes = [f"the simulation blew up at t={t}.00 s; restored the checkpoint of t=0.00 s"
             for t in (3, 9)]
    print_notes({"log": "x.jsonl", "warnings": [], "blowups": notes})
    assert capsys.readouterr().err == (
        "x.jsonl: the simulation blew up 2 times (first at t=3.00 s, last at t=9.00 s); "
        "restored the checkpoint of t=0.00 s each time\n")
