"""A checkpoint re-seats the live space in place (``puppet.physics.reseat``): the same
bits as building a fresh space from the snapshot (``snapshot.rebuild`` without a live
space), right away and thousands of steps later, with grasps, the Ctrl+drag spring (a
kinematic body), props pinned to the world, ground contacts and changed parameters;
and a restore whose objects no longer match the live ones builds a fresh space."""

from __future__ import annotations

import math

import pytest
from helpers import swing_joints

from puppet.data.catalog import load_setup
from puppet.physics import snapshot
from puppet.physics.simulation import Simulation

SETUPS = [("luxo-mouse", None), ("cat-bound", None), ("biped-walk", None),
          ("biped-gymnast", "rope"), ("biped-bars", None)]


def _sim(setup) -> Simulation:
    s = load_setup(*setup)
    return Simulation(s.character, s.scene)


_drive = swing_joints  # tests/helpers.py


def _busy(sim: Simulation) -> None:
    _drive(sim, 480)
    c = sim.character
    held, dragged = c.bodies[c.link_order[0]], c.link_order[-1]
    sim.attach("held", c.link_order[0], (0.0, 0.0), tuple(held.position), rigid=True,
               max_torque=30.0)
    x, y = c.bodies[dragged].position
    sim.start_drag(dragged, (0.0, 0.0), (x + 0.05, y + 0.1))
    sim.ground[0].friction = 0.4
    sim.gravity = (0.3, -9.0)
    _drive(sim, 240)


class _Fresh:
    """``snapshot.rebuild`` never re-seating in place (the reference)."""

    def __enter__(self):
        self.rebuild = snapshot.rebuild
        snapshot.rebuild = lambda state, into=None: self.rebuild(state)

    def __exit__(self, *exc):
        snapshot.rebuild = self.rebuild


@pytest.mark.parametrize("setup", SETUPS)
def test_a_checkpoint_in_place_is_bit_identical_to_a_fresh_space(setup):
    live, fresh = _sim(setup), _sim(setup)
    for run in (live, fresh):
        _busy(run)
    space, bodies = live.space, dict(live.character.bodies)
    for _ in range(3):
        data = live.checkpoint()
        with _Fresh():
            assert fresh.checkpoint() == data
        assert live.snapshot() == fresh.snapshot()
        for run in (live, fresh):
            run.move_drag((0.2, 0.5))
            _drive(run, 720)
        assert live.state_vector() == fresh.state_vector()
    assert live.space is space and live.character.bodies == bodies  # re-seated in place
    assert fresh.space is not space
    assert live.seats == fresh.seats == 3


@pytest.mark.parametrize("setup", SETUPS[:2] + SETUPS[3:])
def test_a_restore_in_place_replays_the_same_across_grasps_made_and_let_go(setup):
    sim = _sim(setup)
    _busy(sim)
    grasping = sim.checkpoint()  # a rigid grasp (pivot and gear) and the drag spring
    _drive(sim, 480)
    straight = sim.state_vector()
    space = sim.space
    sim.restore(grasping)
    assert sim.space is space
    _drive(sim, 480)
    assert sim.state_vector() == straight
    # let go and grasp with another link: the snapshot's joints are gone, others came
    sim.detach("held")
    sim.end_drag()
    c = sim.character
    sim.attach("other", c.link_order[1], (0.0, 0.0), tuple(c.bodies[c.link_order[1]].position))
    _drive(sim, 48)
    view = sim.space.constraints
    sim.restore(grasping)
    assert sim.space is space and set(sim.grasps) == {"held"} and sim.drag_spring is not None
    # pymunk's list of constraints is Chipmunk's, in the same order
    assert [c._constraint for c in sim.space.constraints] == _constraints(sim)
    assert list(view) == list(sim.space.constraints)  # the same dict, not a new one
    _drive(sim, 480)
    assert sim.state_vector() == straight


def _constraints(sim) -> list:
    """The constraints Chipmunk holds, in its order."""
    from pymunk._chipmunk_cffi import ffi, lib

    out: list = []
    handle = ffi.new_handle(out)
    lib.cpSpaceEachConstraint(sim.space._space, lib.ext_cpSpaceConstraintIteratorFunc, handle)
    return out


def test_a_restore_whose_shapes_no_longer_match_builds_a_fresh_space():
    import pymunk

    sim = _sim(SETUPS[0])
    _busy(sim)
    data = sim.checkpoint()
    _drive(sim, 480)
    straight = sim.state_vector()
    space = sim.space
    space.add(pymunk.Circle(space.static_body, 0.1, (5.0, 5.0)))
    sim.restore(data)
    assert sim.space is not space
    _drive(sim, 480)
    assert sim.state_vector() == straight


def test_reseating_in_place_frees_the_arbiters_it_made(monkeypatch):
    import gc

    freed: list = []
    free = snapshot._libc_free

    def record(address):
        freed.append(address)
        free(address)

    gc.collect()  # the spaces of the tests before: their arbiters are freed now, not below
    monkeypatch.setattr(snapshot, "_libc_free", record)
    sim = _sim(SETUPS[2])
    _drive(sim, 480)
    sim.checkpoint()
    made = sim.space._puppet_made
    assert made, "a standing figure has cached contacts to restore"
    first = list(made)
    assert freed == []
    sim.step(24)
    sim.checkpoint()
    assert sim.space._puppet_made is made and freed == first  # the first seat's, once
    second = list(made)
    assert second and not set(second) & set(first)
    del sim, made
    gc.collect()
    ours = set(first + second)
    # the last seat's with the space, each of this space's arbiters freed once (another
    # test's left-over space may be collected here too: its frees are not this one's)
    assert [a for a in freed if a in ours] == first + second


def _space_of_every_kind():
    """Every class the re-seat knows, a polygon of 8 corners (its planes allocated),
    a static floor, a kinematic mover, a one-argument pivot."""
    import pymunk

    space = pymunk.Space()
    space.gravity = (0.0, -9.81)
    space.iterations = 30
    floor = pymunk.Segment(space.static_body, (-5.0, 0.0), (5.0, 0.0), 0.05)
    floor.friction = 0.8
    a, b = pymunk.Body(), pymunk.Body()
    a.position, b.position = (0.0, 0.6), (0.4, 0.9)
    octagon = [(0.2 * math.cos(k * math.pi / 4), 0.2 * math.sin(k * math.pi / 4))
               for k in range(8)]
    shapes = [pymunk.Poly(a, octagon, radius=0.01), pymunk.Circle(b, 0.1, (0.05, 0.0)),
              pymunk.Segment(b, (-0.2, 0.0), (0.2, 0.0), 0.02)]
    for k, shape in enumerate(shapes):
        shape.mass = 1.0 + k
        shape.friction = 0.6
    shapes[1].filter = pymunk.ShapeFilter(group=1)
    mover = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    mover.position, mover.velocity = (1.0, 1.5), (0.1, 0.0)
    space.add(a, b, mover, *shapes, floor)
    joints = [pymunk.PivotJoint(a, b, (0.2, 0.7)), pymunk.RotaryLimitJoint(a, b, -0.5, 0.5),
              pymunk.DampedRotarySpring(a, b, 0.3, 20.0, 1.0),
              pymunk.GearJoint(a, space.static_body, 0.0, 1.0),
              pymunk.DampedSpring(mover, b, (0.0, 0.0), (0.1, 0.0), 0.5, 50.0, 2.0)]
    joints[3].max_force = 5.0
    # a pendulum swinging about its origin, its centre of gravity well off it
    bob = pymunk.Body()
    bob.position = (0.9, 0.9)
    weight = pymunk.Circle(bob, 0.05, (-0.5, -0.5))
    weight.mass = 0.5
    weight.filter = pymunk.ShapeFilter(categories=0, mask=0)
    space.add(bob, weight, pymunk.PivotJoint(bob, space.static_body, (0.0, 0.0), bob.position),
              *joints)
    return space


def test_every_kind_of_object_reseats_in_place_as_a_fresh_space_is_built():
    from puppet.physics.simulation import step_space

    live, fresh = _space_of_every_kind(), _space_of_every_kind()
    for space in (live, fresh):
        step_space(space, 1 / 480, 300)
    for _ in range(12):
        state = snapshot.capture(live, {})
        assert state[6], "the polygon should rest on the floor (cached contacts)"
        assert snapshot.capture(fresh, {}) == state
        fresh, _ = snapshot.rebuild(snapshot.capture(fresh, {}))  # its own snapshot
        same, _ = snapshot.rebuild(state, into=live)
        assert same is live and fresh is not live
        assert snapshot.capture(live, {}) == snapshot.capture(fresh, {})
        for space in (live, fresh):
            step_space(space, 1 / 480, 37)
    assert snapshot.capture(live, {}) == snapshot.capture(fresh, {})


def test_positions_not_made_by_a_step_come_back_to_the_same_bits():
    """Snapshot values a step did not make (a body's position and angle moved by
    hand) re-seat in place as they build a fresh space."""
    import random

    from puppet.physics.simulation import step_space

    rng = random.Random(0)
    live = _space_of_every_kind()
    step_space(live, 1 / 480, 300)
    for _ in range(40):
        state = list(snapshot.capture(live, {}))
        state[1] = [(kind, mass, moment,
                     (force, angle + rng.uniform(-0.5, 0.5),
                      (x + rng.uniform(-0.1, 0.1), y + rng.uniform(-0.1, 0.1)), *rest))
                    for kind, mass, moment, (force, angle, (x, y), *rest) in state[1]]
        state = tuple(state)
        fresh, _ = snapshot.rebuild(state)
        snapshot.rebuild(state, into=live)
        assert snapshot.capture(live, {}) == snapshot.capture(fresh, {})
        step_space(live, 1 / 480, 37)


def test_the_pymunk_in_use_is_one_the_reseat_was_checked_against():
    import pymunk

    from puppet.physics import reseat

    assert reseat.ENABLED, f"pymunk {pymunk.version}: re-verify reseat, then add it to VERIFIED"


def _malformed(state: tuple) -> list:
    """Copies of ``state`` with one record that does not unpack or convert."""
    space_values, bodies, static, shapes, constraints, *rest = state
    poly = next(i for i, r in enumerate(shapes) if len(r[2][0]) > 6)
    cls, body, (verts, transform, radius), *v = shapes[poly]
    bad_poly = [*shapes]
    bad_poly[poly] = (cls, body, ((*verts[:-1], (0.1, "x")), transform, radius), *v)
    bad_body = [*bodies]
    kind, mass, moment, values = bodies[-1]
    bad_body[-1] = (kind, mass, moment, (values[0], "angle", *values[2:]))
    bad_joint = [*constraints]
    cls, a, b, args, values = constraints[-1]
    bad_joint[-1] = (cls, a, b, args, ("strong", *values[1:]))
    bad_space = (*space_values[:-1], -1)  # a collision persistence below zero
    return [(space_values, bodies, static, bad_poly, constraints, *rest),
            (space_values, bad_body, static, shapes, constraints, *rest),
            (space_values, bodies, static, shapes, bad_joint, *rest),
            (bad_space, bodies, static, shapes, constraints, *rest)]


def test_a_record_that_does_not_unpack_raises_before_the_space_is_touched():
    """A malformed record, or a pymunk attribute gone or of another type, raises
    before ``cpSpaceDestroy``: the space is as it was, steps, re-seats and is freed."""
    import gc

    from puppet.physics.simulation import step_space

    live = _space_of_every_kind()
    step_space(live, 1 / 480, 300)
    state = snapshot.capture(live, {})
    for bad in _malformed(state):
        with pytest.raises((TypeError, ValueError, OverflowError)):
            snapshot.rebuild(bad, into=live)
        assert snapshot.capture(live, {}) == state
    shape, body = list(live.shapes)[0], list(live.bodies)[0]
    handle = shape._h
    shape._h = 12345  # not a pointer: the user data setter would raise
    with pytest.raises(TypeError):
        snapshot.rebuild(state, into=live)
    shape._h = handle
    cp_body = body._body
    body._body = None  # a body handle of the wrong type
    with pytest.raises(TypeError):
        snapshot.rebuild(state, into=live)
    body._body = cp_body
    assert snapshot.capture(live, {}) == state
    step_space(live, 1 / 480, 37)  # untouched: steps as it would have
    after = snapshot.capture(live, {})
    fresh, _ = snapshot.rebuild(after)
    assert snapshot.rebuild(after, into=live)[0] is live
    for space in (live, fresh):
        step_space(space, 1 / 480, 240)
    assert snapshot.capture(live, {}) == snapshot.capture(fresh, {})
    del live, fresh, shape, body
    gc.collect()


def test_a_ctrl_c_during_the_reseat_is_raised_once_the_space_is_whole(monkeypatch):
    import signal

    from puppet.physics import reseat
    from puppet.physics.simulation import step_space

    live, fresh = _space_of_every_kind(), _space_of_every_kind()
    for space in (live, fresh):
        step_space(space, 1 / 480, 300)
    state = snapshot.capture(live, {})
    set_iterations = reseat._SPACE_SET[0]

    def interrupted(space, value):  # the user presses Ctrl+C mid-way through commit
        signal.raise_signal(signal.SIGINT)
        set_iterations(space, value)

    monkeypatch.setattr(reseat, "_SPACE_SET", (interrupted, *reseat._SPACE_SET[1:]))
    # Python's own Ctrl+C handler, whatever this process started with (a job started in
    # the background of a shell starts with SIGINT ignored, and Python keeps it so)
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            snapshot.rebuild(state, into=live)
    finally:
        signal.signal(signal.SIGINT, before)
    monkeypatch.undo()
    fresh, _ = snapshot.rebuild(state)
    assert snapshot.capture(live, {}) == snapshot.capture(fresh, {})
    for space in (live, fresh):
        step_space(space, 1 / 480, 240)
    assert snapshot.capture(live, {}) == snapshot.capture(fresh, {})


def test_a_reader_made_before_a_seat_reads_the_rows_of_the_seated_space():
    """The first re-seat puts the space's own static body last among the static ones
    (a new space's order; the scene built it first): a body reader finds the rows
    again (biped-bars: the bars' and the platform's bodies)."""
    from puppet.physics.body_state import WIDTH, BodyReader

    sim = _sim(SETUPS[4])
    _drive(sim, 240)
    space = sim.space
    bodies = [*space.bodies, space.static_body]
    reader = BodyReader()
    before = {b: reader.offset(space, b) for b in bodies}
    sim.checkpoint()
    assert sim.space is space
    fresh = BodyReader()
    after = {b: fresh.offset(space, b) for b in bodies}
    assert after != before, "the seat should change the body order (else no test)"
    assert {b: reader.offset(space, b) for b in bodies} == after
    rows = reader.read(space)
    for b in bodies:
        i = after[b]
        assert rows[i:i + WIDTH][:3] == [*b.position, b.angle]


def test_what_only_a_fresh_space_handles_falls_back_to_it():
    """Sleeping bodies, a custom body velocity/position function, a constraint's
    solve callback: ``live_objects`` says no, the checkpoint builds a fresh space."""
    from puppet.physics import reseat

    def sleepy(sim):
        sim.space.sleep_time_threshold = 0.5

    def velocity(sim):
        body = list(sim.space.bodies)[0]
        body.velocity_func = lambda b, g, damping, dt: None

    def position(sim):
        list(sim.space.bodies)[0].position_func = lambda b, dt: None

    def pre_solve(sim):
        next(iter(sim.space.constraints)).pre_solve = lambda c, s: None

    def post_solve(sim):
        next(iter(sim.space.constraints)).post_solve = lambda c, s: None

    for change in (sleepy, velocity, position, pre_solve, post_solve):
        sim = _sim(SETUPS[0])
        _drive(sim, 48)
        space = sim.space
        assert reseat.live_objects(space, snapshot.capture(space, {})) is not None
        change(sim)
        assert reseat.live_objects(space, snapshot.capture(space, {})) is None
        sim.checkpoint()
        assert sim.space is not space, change.__name__


def test_the_space_setters_are_the_c_calls_behind_the_properties_the_snapshot_lists():
    from puppet.physics import reseat

    names = ["cpSpaceSet" + "".join(w.title() for w in a.split("_"))
             for a in snapshot.SPACE_ATTRS]
    assert [f.__name__ for f in reseat._SPACE_SET] == names
