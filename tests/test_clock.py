"""Slowdown: log-spaced 1x..100x; wall time turns into the right number of steps."""

import math

from puppet.app.clock import SLOWDOWNS, SimClock
from puppet.interface.app_keys import SetSlowdown


def test_slowdowns_are_log_spaced_from_1_to_100():
    assert SLOWDOWNS[0] == 1 and SLOWDOWNS[-1] == 100
    ratios = [b / a for a, b in zip(SLOWDOWNS, SLOWDOWNS[1:])]
    assert max(ratios) / min(ratios) < 1.02


def test_slowdown_sets_simulated_time_per_wall_second():
    for slowdown in (1.0, 10.0, 100.0):
        clock = SimClock(1 / 480, slowdown)
        steps = sum(clock.steps_for(1 / 60) for _ in range(600))  # 10 wall seconds
        assert math.isclose(steps / 480, 10 / slowdown, rel_tol=0.01)


def test_keys_move_the_slowdown_and_pause_stops_time():
    clock = SimClock(1 / 480, 1.0)
    clock.slower()
    clock.slower()
    assert clock.slowdown == SLOWDOWNS[2]
    clock.faster()
    assert clock.slowdown == SLOWDOWNS[1]
    clock.toggle_pause()
    assert clock.steps_for(1.0) == 0


def test_measured_rate():
    clock = SimClock(1 / 480, 10.0)
    for i in range(61):
        clock.sample(i / 60, i / 600)
    assert math.isclose(clock.measured_slowdown(), 10.0, rel_tol=1e-6)


def test_apply_takes_the_speed_actions_and_says_so():
    clock = SimClock(1 / 480, 1.0)
    assert clock.apply("slower") and clock.slowdown == SLOWDOWNS[1]
    assert clock.apply("faster") and clock.slowdown == 1
    assert clock.apply(SetSlowdown(4)) and clock.slowdown == 4
    assert clock.steps_for(0.1) == 12  # 0.1 wall s at 4x: 0.025 simulated s
    assert clock.apply(SetSlowdown(250)) and clock.slowdown == 100
    # not speed: pause is the viewer's (a replay's steps already hold what a pause did)
    for other in ("pause", "quit", "help", None):
        assert not clock.apply(other)
    assert clock.slowdown == 100 and not clock.paused


def test_a_chosen_slowdown_below_1_fast_forwards_and_the_keys_stop_at_real_time():
    clock = SimClock(1 / 480, 0.25)
    assert clock.steps_for(0.05) == 96  # 0.05 wall s at 4x speed: 0.2 simulated s
    clock.faster()
    assert clock.slowdown == 0.25  # the faster key does not slow a fast-forward down
    clock.slower()
    assert clock.slowdown > 1
    assert SimClock(1 / 480, 0.001).slowdown == 0.1


def test_cli_slowdown_out_of_range_is_a_one_line_error():
    import subprocess
    import sys
    from pathlib import Path

    for bad in ("0", "-2", "500", "fast"):
        proc = subprocess.run([sys.executable, "-m", "puppet", "replay",
                               "assets/logs/luxo-hop.jsonl", "--slowdown", bad],
                              capture_output=True, text=True, timeout=60,
                              cwd=Path(__file__).resolve().parents[1])
        assert proc.returncode == 2 and "Traceback" not in proc.stderr
        assert "is not a slowdown from 0.1 to 100" in proc.stderr


def test_the_slower_key_climbs_the_table_to_100x_and_stops_there():
    clock = SimClock(1 / 480, 1.0)
    seen = [clock.slowdown]
    for _ in range(len(SLOWDOWNS) + 5):
        clock.slower()
        seen.append(clock.slowdown)
    assert seen[:len(SLOWDOWNS)] == list(SLOWDOWNS)
    assert seen[len(SLOWDOWNS):] == [100] * 6
    steps = sum(clock.steps_for(0.05) for _ in range(200))  # 10 wall s at 100x: 0.1 sim s
    assert steps == 48
    clock.faster()
    assert clock.slowdown == SLOWDOWNS[-2] < 100
