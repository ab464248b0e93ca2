"""The control tick's prepared paths write what the reference writes, step for step.

A reach's step on the kernel (``ReachController.tick``: a row per reach, made once),
frame targets' kept ``pk_frame`` arguments, a state entry's prepared pose writes
(``poses.pose_writer``), a state's kept transitions plan and a binding's kept pose
targets: each shipped log is played once on them and once on the reference
(``_tick_general``, the arguments made afresh at each solve, ``apply_pose``, the plans
made again at every entry, feedback's plan asked for at every change of the
active maps), and every servo's target and gains, the schedule, the
states and the owners must be the same at every step, also after a restore (the
springs re-bound) and with a link's angle made infinite (a sensor's non-finite input:
NaN targets, then the session's blow-up recovery)."""

from __future__ import annotations

import hashlib
import math
import struct

import pytest
from kernel_paths import needs_cc

from puppet.interface.actions import Actions
from puppet.interface.controllers.feedback import Feedback
from puppet.interface.controllers.frame import FrameTargets
from puppet.interface.controllers.reach import ReachController
from puppet.interface.controllers.state_machine import StateMachine
from puppet.interface.poll_plan import PollPlan
from puppet.interface.poses import apply_pose
from puppet.interface.runtime import InterfaceRuntime
from puppet.physics.servo import GET_TARGET


def _reference(monkeypatch) -> None:
    """Every prepared path replaced by the reference it stands for."""
    monkeypatch.setattr(ReachController, "tick", ReachController._tick_general)
    frames_tick, solve = FrameTargets.tick, FrameTargets._solve

    def fresh_tick(self, step):
        self._args = {}  # (each joint's arguments made again: the reference's lookups)
        return frames_tick(self, step)

    def fresh_solve(self, joint, target):
        self._args = {}
        return solve(self, joint, target)
    monkeypatch.setattr(FrameTargets, "tick", fresh_tick)
    monkeypatch.setattr(FrameTargets, "_solve", fresh_solve)

    def plain_writer(self, pose):
        servos = self.character.servos
        return lambda frames, owner: apply_pose(servos, pose, frames=frames, owner=owner)
    monkeypatch.setattr(Actions, "_pose_writer", plain_writer)
    now_in = StateMachine._now_in

    def fresh_now_in(self, state):
        self._plans = {}
        return now_in(self, state)
    monkeypatch.setattr(StateMachine, "_now_in", fresh_now_in)
    set_maps = Feedback.set_maps

    def fresh_maps(self, readers, setters, adders):
        self.readers = None  # (the plan asked for again)
        return set_maps(self, readers, setters, adders)
    monkeypatch.setattr(Feedback, "set_maps", fresh_maps)
    use_binding = InterfaceRuntime._use_binding

    def fresh_binding(self, binding):
        self.__dict__.pop("_pose_targets", None)
        return use_binding(self, binding)
    monkeypatch.setattr(InterfaceRuntime, "_use_binding", fresh_binding)


def _digest(session) -> str:
    """Every servo's target and gains (their bits: NaN too), the schedule, the states
    and the owners."""
    rt = session.runtime
    bits = []
    for servo in session.sim.character.servos.values():
        spring = servo.spring
        bits.append(struct.pack("<4d", GET_TARGET(spring._constraint), spring.stiffness,
                                spring.damping, spring.max_force))
    bits.append(repr((rt.next_wakeup, rt.states, sorted(rt.owners.table.items()),
                      sorted(rt.frames.held), sorted(rt.reaches))).encode())
    return hashlib.sha1(b"".join(bits)).hexdigest()


def _played(name: str, steps: int, infinite: tuple[int, str] | None = None,
            restore_at: int | None = None) -> list[str]:
    """A shipped log played one step at a time: the digest after each step (and the
    end's state hash). ``infinite``: (step, link) whose angle is made infinite there;
    ``restore_at``: a step at which the last checkpoint is restored (re-bound
    springs and bodies)."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(f"assets/logs/{name}.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    feeder = LogFeeder(session, log)
    out, kept = [], []
    for step in range(steps):
        if infinite is not None and step == infinite[0]:
            session.sim.character.bodies[infinite[1]].angle = math.inf
        if step == restore_at:  # (the old space kept alive: the restored one's objects
            kept.append((session.sim.space, session.sim.character.bodies))  # elsewhere)
            session.restore_checkpoint()
            feeder = LogFeeder(session, log)  # (its events after the restored step)
            feeder.i = sum(1 for at, _ in feeder.events if at <= session.sim.steps)
        feeder.advance(1)
        out.append(_digest(session))
    out.append(session.sim.state_hash())
    return out


def _first_difference(fast: list[str], reference: list[str]):
    for i, (a, b) in enumerate(zip(fast, reference)):
        if a != b:
            return i
    return None if len(fast) == len(reference) else min(len(fast), len(reference))


CASES = [  # (log, steps, a link made infinite at a step, a restore)
    ("biped-auto-walk", 4200, None, 3100),  # frame targets, gait entries, re-binding
    ("biped-auto-walk", 3200, (3000, "thigh_near"), None),  # feedback's sensor: NaN
    ("biped-auto-run", 14400, None, None),  # the run's entries (role sensors)
    ("biped-ladder-climb", 5200, None, 4100),  # three reaches at every step
    ("biped-ladder-climb", 2600, (1000, "chest"), None),  # a reach's rotation: NaN
    ("biped-monkey-bars", 4000, None, None),  # reaches that grasp on arrival
]


@needs_cc
@pytest.mark.parametrize("name, steps, infinite, restore_at", CASES,
                         ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_the_prepared_tick_writes_what_the_reference_writes(path_of, monkeypatch, name,
                                                            steps, infinite, restore_at):
    path_of("c")
    fast = _played(name, steps, infinite, restore_at)
    _reference(monkeypatch)
    reference = _played(name, steps, infinite, restore_at)
    assert _first_difference(fast, reference) is None


def test_the_prepared_entries_write_what_the_reference_writes_in_python(path_of, monkeypatch):
    """On the pure-Python path (no kernel: reaches and frame targets are the general
    loops) the prepared pose writes and kept plans are still the reference's."""
    path_of("python")
    fast = _played("biped-auto-walk", 2600, None, 2000)
    _reference(monkeypatch)
    assert _first_difference(fast, _played("biped-auto-walk", 2600, None, 2000)) is None


@needs_cc
def test_a_reach_row_is_made_again_when_a_reach_starts_ends_or_is_restored(path_of,
                                                                            monkeypatch):
    """The reach rows (``_planned``) follow the running reaches: after every tick they
    are the running reaches' on the bodies of now (a start, an end and a re-seat each
    make them again); between those, a step reuses them."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    path_of("c")
    tick, seen = ReachController.tick, {"plans": set(), "reused": 0}

    def checked(self, step):
        before = self._plan
        got = tick(self, step)
        plan = self._plan
        if plan is not None:
            assert [row[0] for row in plan[1]] == list(self.reaches)
            assert all(row[1] is self.reaches[row[0]] for row in plan[1])
            assert plan[0] is self.character.bodies
            seen["reused"] += plan is before
            seen["plans"].add(id(plan))
        return got
    monkeypatch.setattr(ReachController, "tick", checked)
    # (every tick Python's: the kernel's loop runs the reaches between a climb's
    # events, from the same rows, ``poll_reach``; test_poll_reach holds it equal)
    monkeypatch.setattr(PollPlan, "ready", lambda self, step, idle=False: None)
    log = read_log("assets/logs/biped-ladder-climb.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    LogFeeder(session, log).advance(6000)
    assert len(seen["plans"]) > 3 and seen["reused"] > 1000, seen


def test_a_states_kept_plan_is_the_one_of_its_binding():
    """A state entered under one binding and then re-bound (a gait's entry runs
    ``enter`` before its roles) polls the new binding's transitions: the kept plan
    is the one ``_state_plan`` makes for them."""
    from puppet.data.catalog import load_setup
    from puppet.session.session import Session

    session = Session(load_setup("biped-auto"), keyframes=False)
    rt = session.runtime
    machine = rt.machines["main"]
    for state, binding in [("down_far", "near"), ("down_far", "far"), ("run_near", "far"),
                           ("run_near", "near"), ("down_near", "far"),
                           ("down_near", "near")] * 2:
        machine.enter(state, 0)
        rt._use_binding(binding)
        assert machine._transitions is machine.transitions[state], (state, binding)
        assert (machine._transitions, machine._polled, machine._timer, machine._one_sensor,
                machine._held) == machine._state_plan(state)
        assert rt.pose_targets == {n: p.targets for n, p in rt.poses.items()}


def _frame_targets_now(session) -> dict:
    servos = session.sim.character.servos
    return {j: GET_TARGET(servos[j].spring._constraint) for j in session.runtime.frames.held}


def _ticked_twice(session, step: int) -> tuple[dict, dict]:
    """Frame targets after a tick on the kept arguments, then after one on arguments
    made afresh (the reference) from the same state of the figure."""
    frames = session.runtime.frames
    frames.tick(step)
    kept = _frame_targets_now(session)
    frames._args = {}
    frames.tick(step)
    return kept, _frame_targets_now(session)


@needs_cc
def test_frame_targets_kept_arguments_follow_new_targets_and_re_bound_bodies(path_of):
    """The kept ``pk_frame`` arguments are made again for a held joint's new target
    (a restored state: other targets on the same bodies) and for re-bound bodies under
    the same targets."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    path_of("c")
    log = read_log("assets/logs/biped-auto-walk.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    LogFeeder(session, log).advance(3100)
    frames = session.runtime.frames
    step = 3100 - 3100 % frames.every
    assert len(frames.held) >= 3
    frames.tick(step)  # (the arguments kept)
    state = frames.get_state()
    for held in state.values():
        held[0][1] += 0.1  # the angle: other targets, the same bodies
    frames.set_state(state)
    kept, fresh = _ticked_twice(session, step)
    assert kept == fresh
    # re-bound bodies under the same targets (a restore makes the bodies' dict anew, its
    # objects anew where the space is rebuilt): the kept arguments must go, even though
    # their targets are the held ones (made wrong here, so that using them shows)
    frames.tick(step)
    frames._args = {j: (t, (*a[:3], a[3] + 1.0, *a[4:])) for j, (t, a) in frames._args.items()}
    character = session.sim.character
    character.bodies = dict(character.bodies)
    kept, fresh = _ticked_twice(session, step)
    assert kept == fresh and kept


def _reference_try_grasp(self, name, points=None, prop=None, tolerance=0.04, rigid=False,
                         max_torque=None, skip_released=False) -> bool:
    """``GraspController.try_grasp`` as it was before the prepared path (the prop's
    box and its nearest place each looking at where it stands)."""
    if self.sim is None or self.holds(name):
        return self.holds(name)
    chain = self.chains[name]
    ex, ey = chain.end_world(self.character)
    props = self.sim.props
    if points is None:
        names = [n for n in (props if prop == "any" else [prop])
                 if not props[n].beyond((ex, ey), tolerance)]
        if not names:
            return False
    skip = self.released_point(name) if skip_released else None
    exclude = None if skip is None else (skip[0], skip[1], tolerance)
    if points is not None:
        for p in points:
            if exclude is not None and math.hypot(p[0] - skip[0], p[1] - skip[1]) < tolerance:
                continue
            if math.hypot(ex - p[0], ey - p[1]) <= tolerance:
                self.sim.attach(name, chain.end_link, chain.end, (p[0], p[1]), prop,
                                rigid, max_torque)
                return True
        return False
    found = [(*props[n].nearest((ex, ey), exclude)[:2], n) for n in names]
    distance, point, which = min(found, key=lambda f: f[0])
    if distance <= tolerance:
        self.sim.attach(name, chain.end_link, chain.end, point, which, rigid, max_torque)
        return True
    return False


def test_a_grasp_try_catches_what_the_reference_catches():
    """An armed grasp's try (one look at where each prop stands for its box and its
    nearest place) answers and attaches as the reference does: places within reach
    and not, on each prop and on "any", where a chain let go, and an end at a
    non-finite place."""
    import random

    from puppet.data.catalog import load_setup
    from puppet.interface.controllers.grasp import GraspController
    from puppet.session.session import Session

    session = Session(load_setup("biped-bars"), keyframes=False)
    grasps, sim = session.runtime.grasping, session.sim
    made = []
    sim.attach = lambda *args: made.append(args)  # (recorded, not pinned: tried again)
    rng = random.Random(5)
    bars = sim.props["bars"]
    places = [(x, y) for _, x, y in bars._placed()[0]]
    chain = grasps.chains["hand_near"]
    body = sim.character.bodies[chain.end_link]
    grasps.released["hand_near"] = ("bars", bars.points[next(iter(bars.points))])
    answers, caught = set(), set()
    for i in range(600):
        px, py = places[i % len(places)]
        r = rng.choice([0.0, 0.02, 0.039, 0.041, 0.1, 0.5, 3.0])
        ox, oy = chain.end_world(sim.character)  # (the end where the place is)
        bx, by = body.position
        body.position = (bx + px - ox + rng.uniform(-r, r), by + py - oy + rng.uniform(-r, r))
        if i % 97 == 0:
            body.position = (math.nan, py) if i % 2 else (math.inf, -math.inf)
        elif i % 97 == 1:
            body.position = (0.0, 0.0)
        for prop in ("bars", "platform", "any"):
            for skip in (False, True):
                args = ("hand_near", None, prop, rng.choice([0.04, 0.2]), False, None, skip)
                made.clear()
                got = (grasps.try_grasp(*args), list(made))
                made.clear()
                want = (_reference_try_grasp(grasps, *args), list(made))
                assert got == want, (i, prop, skip, tuple(body.position))
                answers.add(got[0])
                if got[0] and skip:
                    caught.add(got[1][0][3])
        point = [[px + 0.01, py]]
        made.clear()
        got = (grasps.try_grasp("hand_near", point, "bars", 0.04), list(made))
        made.clear()
        assert got == (_reference_try_grasp(grasps, "hand_near", point, "bars", 0.04),
                       list(made))
    assert answers == {True, False} and len(caught) > 1, caught
    assert GraspController.try_grasp is not _reference_try_grasp
