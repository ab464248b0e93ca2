"""Review of ovhluxo2 (``interface.poll_states``): a case the shipped logs do not
exercise, where the kernel's loop entering states and Python's ticks part."""

from __future__ import annotations

from unittest.mock import patch

from kernel_paths import needs_cc, trace

from puppet.interface import poll_plan
from puppet.timeline import replay as _replay
from puppet.timeline.log import read_log

SHUFFLE = "assets/logs/luxo-shuffle.jsonl"

# the step's end goes into a pair of states that send each other on at once (a timer
# of 0 s): `spin`, entered by nothing, one the loop can enter, and `stiff`, whose
# entry sets a gain (Python's). Python's tick enters MAX_CHAINED_GOTOS (16) states a
# step; the loop enters `spin` and stops for Python's tick at the same step, which
# enters 16 more.
SPIN = """
  spin:
    description: on at once
    control_rate: 480
    transitions:
      - {to: stiff, after: 0.0}
  stiff:
    description: a gain, and on at once
    control_rate: 480
    enter: {stiffness: {ankle: 36}}
    transitions:
      - {to: spin, after: 0.0}
      - {to: rest, after: 100.0}   # (never: rest reachable)
"""


def _spinning(log):
    text = log.header["interface_text"]
    old = "      - {to: rest, after: 0.05}"
    assert text.count(old) == 1
    log.header["interface_text"] = text.replace(old, "      - {to: spin, after: 0.05}") \
        .rstrip() + "\n" + SPIN
    return log


def _traced(log, loop: bool):
    setup = _replay.setup_for_log
    with patch.object(_replay, "setup_for_log", lambda lg, *a, **k: setup(lg, as_recorded=True)):
        if loop:
            return trace(log, True)[0]
        with patch.object(poll_plan.PollPlan, "ready", lambda *a, **k: None):
            return trace(log, True)[0]


@needs_cc
def test_a_chain_the_loop_starts_and_python_ends(path_of):
    assert path_of("c") is not None
    log = _spinning(read_log(SHUFFLE))
    with_loop, ticks = _traced(log, True), _traced(log, False)
    assert len(with_loop) == len(ticks)
    spun = [a[0] for a in ticks if a[1]["machines"]["main"][0] in ("spin", "stiff")]
    assert spun  # the pair is reached
    for a, b in zip(with_loop, ticks):
        # (fails at 182: the loop's run ends in ['spin', 181], Python's ticks in
        # ['stiff', 181]: 17 states entered at step 181, not 16; the physics' hash the
        # same here, the entries being idempotent)
        assert a[0] == b[0] and a[1]["machines"] == b[1]["machines"], (a[0], a[1]["machines"],
                                                                      b[1]["machines"])
