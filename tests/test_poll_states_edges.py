"""The kernel's loop entering states (``interface.poll_states``) in cases no shipped
log has: a press kept for a state (the plan filled again, so disarmed), a chain the
loop starts and Python's tick ends (at most MAX_CHAINED_GOTOS at a step in all), a
mode changed under a state the loop enters, checkpoints restored with states the loop
entered; each against Python's ticks and the pure-Python path."""

from __future__ import annotations

from kernel_paths import needs_cc, restored_run, traced_edited

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


@needs_cc
def test_a_chain_the_loop_starts_and_python_ends(path_of):
    log = _spinning(read_log(SHUFFLE))
    with_loop, ticks = _paths(lambda: log, path_of)
    spun = [a[0] for a in ticks if a[1]["machines"]["main"][0] in ("spin", "stiff")]
    assert spun  # the pair is reached
    for a, b in zip(with_loop, ticks):
        # (failed at 182 before runtime.chained: the loop's run ended in ['spin', 181],
        # Python's ticks in ['stiff', 181]: 17 states entered at step 181, not 16; the
        # physics' hash the same here, the entries being idempotent)
        assert a[0] == b[0] and a[1]["machines"] == b[1]["machines"], (a[0], a[1]["machines"],
                                                                      b[1]["machines"])


# a key bound in `extend` alone, kept (``buffer``) when pressed in `fold`: Python's
# ``_enter_state`` runs it as `extend` is entered; the loop enters `extend` itself
KEPT = "      - {key: k, adjust: {knee: 30}, buffer: 0.5, description: a kept press}"


def _paths(make, path_of):
    """The log ``make()`` gives traced with the kernel's loop, with Python's ticks on
    the kernel and on the pure-Python path; the last two agree (asserted)."""
    assert path_of("c") is not None
    with_loop, ticks = traced_edited(make(), True), traced_edited(make(), False)
    assert path_of("python") is None
    assert ticks == traced_edited(make(), True)  # (Python's ticks on the kernel and the pure path)
    assert len(with_loop) == len(ticks)
    return with_loop, ticks


def _pressed(log, key: str, at: int):
    """The log with ``key`` pressed at step ``at`` and let go two steps later."""
    pairs = sorted(log.pairs() + [(at, {"type": "key", "key": key, "down": True}),
                                  (at + 2, {"type": "key", "key": key, "down": False})],
                   key=lambda p: p[0])
    log.pairs = lambda: pairs
    return log


def _kept(log, at: int):
    text = log.header["interface_text"]
    old = "    enter: {set: {ankle: -35.0, knee: 78.2623}, over: 0.05}\n"
    assert text.count(old) == 1
    log.header["interface_text"] = text.replace(old, old + "    keys:\n" + KEPT + "\n")
    return _pressed(log, "k", at)


@needs_cc
def test_a_press_kept_for_a_state_the_loop_enters(path_of):
    # 155: a step into the first fold (entered at 154 in Python's ticks)
    with_loop, ticks = _paths(lambda: _kept(read_log(SHUFFLE), 155), path_of)
    # (failed at 157 before poll_plan's key disarmed the plan: the loop's run entered
    # `extend` with the press still kept, {'buffer': {'k': 155}}, the knee the blend's;
    # the hash then 9dd2d3df1b8926a5, not acfd0cf9687b8189, and at the end
    # 7156e1c43167f6e1, not 369281653091b175)
    for a, b in zip(with_loop, ticks):
        assert a[0] == b[0] and a[1] == b[1] and a[3] == b[3] and a[4] == b[4], a[0]



# a key that switches the mode back to the mouse's (its maps on the ankle and knee),
# pressed in `fold`; `extend`'s entry says the helper's mode too (nothing, in that
# mode: the loop's table was made in it): Python's entry of `extend` switches the mode
# back, the loop's would leave the mouse's. Passes: the mode's maps make the tick
# Python's (ready: a controller not the plan's), so `extend` is entered by Python at 156
# (the loop enters only `rest`, at 180); kept as a guard on that
MODE_KEY = "\nkeys:\n  - {key: m, mode: mouse, description: the mouse's mode}\n"


def _moded(log, at: int):
    text = log.header["interface_text"]
    old = "enter: {set: {ankle: -35.0, knee: 78.2623}, over: 0.05}"
    assert text.count(old) == 1
    log.header["interface_text"] = text.replace(old, old[:-1] + ", mode: helper}") \
        .rstrip() + "\n" + MODE_KEY
    return _pressed(log, "m", at)


@needs_cc
def test_a_mode_changed_under_a_state_the_loop_enters(path_of):
    # 155: a step into the first fold (entered at 154 in Python's ticks)
    with_loop, ticks = _paths(lambda: _moded(read_log(SHUFFLE), 155), path_of)
    for a, b in zip(with_loop, ticks):
        assert a[0] == b[0] and a[1] == b[1] and a[3] == b[3] and a[4] == b[4], a[0]


def _restored(loop: bool, checkpoint: int, restore: int):
    """The shuffle with a checkpoint at ``checkpoint`` (in `extend`, its targets
    travelling, or in `rest`) restored at ``restore``, the stream again from the
    checkpoint; the hash and the entries and arrivals the loop handed back."""
    session, n = restored_run(SHUFFLE, loop, checkpoint, restore)
    return session.sim.state_hash(), n


@needs_cc
def test_a_checkpoint_restored_with_states_the_loop_enters(path_of):
    """Passes (coverage): a restore into a state the loop entered, a blend travelling,
    and out of one, the same bits as Python's ticks and the pure path."""
    assert path_of("c") is not None
    cases = [(170, 400), (181, 218), (405, 950)]
    with_loop = [_restored(True, c, r) for c, r in cases]
    ticks = [_restored(False, c, r) for c, r in cases]
    assert all(n > 100 for _, n in with_loop) and all(n == 0 for _, n in ticks)
    assert path_of("python") is None
    in_python = [_restored(True, c, r) for c, r in cases]
    assert [h for h, _ in with_loop] == [h for h, _ in ticks] == [h for h, _ in in_python]
