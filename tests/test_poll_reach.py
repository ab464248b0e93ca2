"""A running reach inside the kernel's stepping loop (``poll_reach``, ``pk_poll``'s
``pk_reaches``), and several state machines in one table (``poll_machines``): the logs
whose reaches the loop runs (the ladder climb's hands and feet on their rungs,
grasping on arrival; the Luxo designer's reaches; the monkey bars' hands, with a
second machine, ``legs``), the giant swings' five machines (``pump`` polling the
centre of mass) and the gymnast's climb (armed grasps tried in the loop,
``pk_catches``) replay call by
call to the same states, servo targets and physics bits with the loop, without it
(Python's ticks on the kernel) and on the pure-Python path, fed all at once and a few
steps a call (runs cut at a call's end, going on from there); and the kernel's
``pk_hypot`` is CPython's ``math.hypot`` to the bit.
"""

from __future__ import annotations

import math
import random
import struct
from unittest.mock import patch

import pytest
from kernel_paths import agree_without_the_loop, needs_cc, trace

from puppet.interface import poll_plan
from puppet.timeline.log import read_log

REACHING = ["biped-ladder-climb", "luxo-designer-try", "biped-monkey-bars"]
MACHINES = ["biped-monkey-bars", "biped-giant-swings", "biped-gymnast-climb-bound"]


def _bits(x: float) -> bytes:
    return struct.pack("<d", x)


@needs_cc
def test_pk_hypot_is_pythons(path_of):
    hypot = path_of("c").lib.pk_hypot
    rnd = random.Random(29)
    special = [0.0, -0.0, 5e-324, 1e-310, 2.2250738585072014e-308, 1e-200, 1.0, 3.0, 4.0,
               1e200, 1.7976931348623157e308, math.inf, -math.inf, math.nan]
    pairs = [(a, b) for a in special for b in special]
    for _ in range(200_000):
        pairs.append((rnd.uniform(-2.0, 2.0), rnd.uniform(-2.0, 2.0)))
        pairs.append((rnd.gauss(0.0, 1.0) * 10.0 ** rnd.uniform(-15, 15),
                      rnd.gauss(0.0, 1.0) * 10.0 ** rnd.uniform(-15, 15)))
        a = rnd.uniform(-1.0, 1.0)  # (nearly equal, and far apart in size)
        pairs.append((a, a * rnd.uniform(0.999, 1.001) * 1e-3 ** rnd.randint(0, 3)))
    for a, b in pairs:
        assert _bits(hypot(a, b)) == _bits(math.hypot(a, b)), (a, b)


def _traces(name: str, path_of, chunk: int | None, reaches: bool = True) -> None:
    log = read_log(f"assets/logs/{name}.jsonl")
    assert path_of("c") is not None
    run, reaching, many, armed = poll_plan.PollPlan.run, [0], [0], [0]

    def counted(self, *args, **kwargs):
        reaching[0] += self.plan.n_reach > 0
        armed[0] += self.plan.n_armed > 0 and any(self.plan.a_skip[j]
                                                  for j in range(self.plan.n_armed))
        many[0] += self._many
        return run(self, *args, **kwargs)

    with patch.object(poll_plan.PollPlan, "run", counted):
        with_loop, runs, _, _ = trace(log, True, chunk)
    assert reaching[0] > 0 or not reaches, runs  # the loop ran reaches
    assert many[0] > 0 or name not in MACHINES, runs  # ... and several machines
    assert armed[0] > 0 or name != "biped-gymnast-climb-bound", runs  # ... skipping
    agree_without_the_loop(log, with_loop, chunk, path_of)


@needs_cc
@pytest.mark.parametrize("name", REACHING)
def test_the_loop_runs_reaches_as_the_ticks_do(name, path_of):
    _traces(name, path_of, None)


@needs_cc
@pytest.mark.parametrize("name", REACHING)
def test_runs_cut_at_each_call_run_them_alike(name, path_of):
    """Fed 37 steps a call: a reach's run stops at the call's end and the next goes on
    from there (``tick_first``: its aim and writes at that step are the kernel's)."""
    _traces(name, path_of, 37)


@needs_cc
@pytest.mark.parametrize("name", ["biped-giant-swings"])
def test_the_loop_polls_several_machines_as_the_ticks_do(name, path_of):
    """Five machines, one polling the centre of mass (``pump``), in one table, whole
    and 37 steps a call."""
    _traces(name, path_of, None, reaches=False)
    _traces(name, path_of, 37, reaches=False)


@needs_cc
@pytest.mark.parametrize("name", ["biped-gymnast-climb-bound"])
def test_the_loop_tries_armed_grasps_as_the_ticks_do(name, path_of):
    """Hands and feet armed on every prop, each skipping where it let go, tried in
    the loop at every step, whole and 37 steps a call."""
    _traces(name, path_of, None, reaches=False)
    _traces(name, path_of, 37, reaches=False)
