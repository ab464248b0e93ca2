"""Simulation snapshots: the hand-written format restores exactly what pymunk's pickle did.

``restore`` rebuilds a fresh space as unpickling one would; restored runs (every log's
start and its checkpoints) must keep their bits, so the reference here is the pickle
format it replaced: both restores of one mid-motion state (ground contacts, a grasp
joint, the Ctrl+drag spring, changed friction, gravity and servo gains) must agree
bit for bit, right after restoring and 2000 steps later.
"""

from __future__ import annotations

import pickle
import subprocess
import sys
from pathlib import Path

import pymunk
import pytest
from helpers import swing_joints

from puppet.data.catalog import load_setup
from puppet.physics import snapshot
from puppet.physics.simulation import Simulation

SETUPS = ["luxo-mouse", "cat-bound"]


def _legacy_snapshot(sim: Simulation) -> bytes:
    """The format before: pymunk's own pickle of the space and the objects we hold."""
    objects = (sim.space, sim.character.state_objects(), tuple(sim.ground),
               sim.drag_body, sim.drag_spring, sim.steps,
               [(name, joint, prop) for name, (joint, prop) in sim.grasps.items()])
    return pickle.dumps(objects, protocol=pickle.HIGHEST_PROTOCOL)


def _legacy_restore(sim: Simulation, data: bytes) -> None:
    space, character, ground, drag_body, drag_spring, steps, grasps = pickle.loads(data)
    sim.grasps = {name: (joint, prop) for name, joint, prop in grasps}
    sim.space = space
    sim.character.bind(character)
    sim.ground = list(ground)
    sim.drag_body, sim.drag_spring = drag_body, drag_spring
    sim.steps = steps


def _sim(setup: str) -> Simulation:
    s = load_setup(setup)
    return Simulation(s.character, s.scene)


_drive = swing_joints  # tests/helpers.py


def _grasps(sim: Simulation) -> list:
    return [c for c in sim.space.constraints
            if isinstance(c, pymunk.PivotJoint) and c.b is sim.space.static_body]


def _busy(setup: str) -> Simulation:
    """Mid-motion on the ground, one link grasping the world, another dragged."""
    sim = _sim(setup)
    _drive(sim, 480)
    c = sim.character
    held, dragged = c.bodies[c.link_order[0]], c.link_order[-1]
    sim.attach("held", c.link_order[0], (0.0, 0.0), tuple(held.position))  # as a grasp does
    x, y = c.bodies[dragged].position
    sim.start_drag(dragged, (0.0, 0.0), (x + 0.05, y + 0.1))
    sim.ground[0].friction = 0.4
    sim.gravity = (0.3, -9.0)
    servo = next(iter(c.servos.values()))
    servo.stiffness *= 1.2
    servo.max_torque *= 0.9
    _drive(sim, 240)
    assert sim.space._get_arbiters(), "the state should have ground contacts"
    return sim


def test_attributes_are_set_in_pymunks_pickle_order():
    assert [*snapshot.SPACE_ATTRS, "threads"] == pymunk.Space._pickle_attrs_general
    assert list(snapshot.BODY_ATTRS) == pymunk.Body._pickle_attrs_general
    assert list(snapshot.SHAPE_ATTRS) == pymunk.Shape._pickle_attrs_general
    assert list(snapshot.CONSTRAINT_ATTRS) == pymunk.Constraint._pickle_attrs_general
    # and Chipmunk's setters the rebuild calls are those attributes', in that order
    for kind, names, setters in (("Body", snapshot.BODY_ATTRS, snapshot._BODY_SET),
                                 ("Shape", snapshot.SHAPE_ATTRS, snapshot._SHAPE_SET),
                                 ("Constraint", snapshot.CONSTRAINT_ATTRS,
                                  snapshot._CONSTRAINT_SET)):
        want = ["cp" + kind + "Set" + ("HashID" if n == "_hashid" else
                                       "".join(w.title() for w in n.split("_")))
                for n in names]
        assert [f.__name__ for f in setters] == want


@pytest.mark.parametrize("setup", SETUPS)
def test_restore_is_bit_identical_to_restoring_pymunks_pickle(setup):
    sim = _busy(setup)
    old, new = _sim(setup), _sim(setup)
    _legacy_restore(old, _legacy_snapshot(sim))
    data = sim.snapshot()
    assert type(data) is bytes
    new.restore(data)
    # every body, shape, constraint, cached contact and counter, as the format sees them
    assert new.snapshot() == old.snapshot()
    for run in (old, new):
        run.move_drag((0.2, 0.5))
        _drive(run, 2016)
    assert new.state_vector() == old.state_vector()
    assert new.snapshot() == old.snapshot()


@pytest.mark.parametrize("setup", SETUPS)
def test_restored_copies_agree_but_differ_from_the_run_that_was_not_reseated(setup):
    sim = _busy(setup)
    data = sim.snapshot()
    first, second = _sim(setup), _sim(setup)
    first.restore(data)
    second.restore(data)
    for run in (sim, first, second):
        _drive(run, 2016)
    assert first.state_vector() == second.state_vector()
    # pymunk keeps no solver warm-start: hence checkpoint() re-seats the live run
    assert first.state_vector() != sim.state_vector()


@pytest.mark.parametrize("setup", SETUPS)
def test_restoring_a_checkpoint_replays_the_run_that_never_restored(setup):
    sim = _busy(setup)
    data = sim.checkpoint()
    _drive(sim, 2016)
    straight = sim.state_vector()
    sim.restore(data)
    _drive(sim, 2016)
    assert sim.state_vector() == straight


def test_restore_brings_back_joints_springs_gains_and_world_parameters():
    sim = _busy("cat-bound")
    c = sim.character
    servo = c.servos["spine"]
    before = (servo.target, servo.stiffness, servo.damping, servo.max_torque,
              sim.gravity, sim.ground[0].friction)
    data = sim.snapshot()
    sim.end_drag()
    sim.detach("held")
    servo.target, servo.stiffness = 1.0, 5.0
    sim.gravity, sim.ground[0].friction = (0.0, -1.0), 0.9
    sim.restore(data)
    assert (servo.target, servo.stiffness, servo.damping, servo.max_torque,
            sim.gravity, sim.ground[0].friction) == before
    space = sim.space
    assert len(_grasps(sim)) == 1 and _grasps(sim)[0].a is c.bodies[c.link_order[0]]
    assert sim.drag_spring in space.constraints and sim.drag_body in space.bodies
    assert sim.drag_spring.b is c.bodies[c.link_order[-1]]
    assert all(g in space.shapes for g in sim.ground)
    for name, body in c.bodies.items():
        assert body in space.bodies and all(s.body is body for s in c.shapes[name])
    for s in c.servos.values():
        assert s.spring in space.constraints
        assert (s.child, s.parent) == (s.spring.a, s.spring.b)
        assert s.child in space.bodies and s.parent in space.bodies


def test_a_snapshot_restores_in_another_process(tmp_path):
    sim = _busy("cat-bound")
    path = tmp_path / "state.bin"
    path.write_bytes(sim.snapshot())
    sim.restore(path.read_bytes())
    _drive(sim, 960)
    code = ("import sys; sys.path.insert(0, sys.argv[1]);"
            "from test_checkpoint_format import _sim, _drive;"
            "sim = _sim('cat-bound'); sim.restore(open(sys.argv[2], 'rb').read());"
            "_drive(sim, 960); print(sim.state_hash())")
    out = subprocess.run([sys.executable, "-c", code, str(Path(__file__).parent), str(path)],
                         capture_output=True, text=True, check=True)
    assert out.stdout.strip() == sim.state_hash()


def test_the_records_read_what_pymunks_properties_read():
    """The records go through Chipmunk's getters; pymunk's properties (what its pickle
    reads) must give the same values, for each class read that way."""
    a, b = pymunk.Body(2.0, 3.0), pymunk.Body(1.5, 0.5)
    a.position, a.velocity, a.angle, a.force, a.torque = (1, 2), (0.3, -0.4), 0.7, (5, 6), 0.9
    a.center_of_gravity, a.angular_velocity = (0.01, -0.02), 1.25
    shapes = [pymunk.Circle(a, 0.1, (0.2, 0.3)), pymunk.Segment(a, (0, 0), (1, 0.5), 0.02),
              pymunk.Poly(a, [(0, 0), (1, 0), (0.5, 0.8)], radius=0.01)]
    shapes[0].friction, shapes[0].elasticity, shapes[0].surface_velocity = 0.8, 0.1, (1, 2)
    shapes[1].filter, shapes[1].collision_type = pymunk.ShapeFilter(3, 5, 9), 4
    shapes[2].sensor = True
    constraints = [pymunk.PivotJoint(a, b, (0.1, 0.2), (0.3, 0.4)),
                   pymunk.RotaryLimitJoint(a, b, -0.5, 1.5),
                   pymunk.DampedRotarySpring(a, b, 0.25, 300.0, 12.0),
                   pymunk.GearJoint(a, b, 0.3, 1.0)]
    constraints[0].max_force, constraints[1].error_bias, constraints[2].max_bias = 70.0, 0.2, 9.0
    constraints[3].collide_bodies = False
    assert set(snapshot._FAST_INIT) == {type(o) for o in shapes + constraints}
    index = {a: 0, b: 1}
    values = (getattr(a, n) for n in snapshot.BODY_ATTRS)
    assert snapshot._body_record(a) == (a.body_type, a.mass, a.moment,
                                        tuple(tuple(v) if isinstance(v, tuple) else v
                                              for v in values))
    for obj, skip in [(s, 1) for s in shapes] + [(c, 2) for c in constraints]:
        cls = type(obj)
        names = cls._pickle_attrs_init[skip:]
        plain = tuple(tuple(map(tuple, v)) if isinstance(v, list) else
                      tuple(v) if isinstance(v, tuple) else v
                      for v in (getattr(obj, n) for n in names)) if cls is not pymunk.Poly else (
            tuple(map(tuple, obj.get_vertices())), None, obj.radius)
        assert snapshot._init_args(obj, skip) == plain, cls
    for s in shapes:
        record = snapshot._shape_record(s, index)
        assert record[3] == tuple(tuple(v) if isinstance(v, tuple) else v
                                  for v in (getattr(s, n) for n in snapshot.SHAPE_ATTRS))
        assert record[4:] == (s.mass, s.density)
    for c in constraints:
        assert snapshot._constraint_record(c, index)[4] == tuple(
            getattr(c, n) for n in snapshot.CONSTRAINT_ATTRS)


def _typed(values) -> list:
    """(type, value) of each value as a record holds it: pymunk's named tuples (Vec2d,
    ShapeFilter) as plain tuples, a list of points as a tuple of tuples."""
    out = []
    for v in values:
        if isinstance(v, list):
            v = tuple(tuple(p) for p in v)
        elif isinstance(v, tuple):
            v = tuple(v)
        out.append((type(v), v))
    return out


def test_the_records_hold_what_pymunks_own_pickle_state_holds_with_its_types():
    """Against pymunk's ``__getstate__`` (what its pickle writes), value and type: a
    getter giving 1 for True, or a Vec2d for a tuple, would change the snapshot bytes."""
    a, b = pymunk.Body(2.0, 3.0), pymunk.Body(1.5, 0.5)
    a.position, a.velocity, a.angle, a.angular_velocity = (1, 2), (0.3, -0.4), 0.7, 1.25
    shapes = [pymunk.Circle(a, 0.1, (0.2, 0.3)), pymunk.Segment(a, (0, 0), (1, 0.5), 0.02),
              pymunk.Poly(a, [(0, 0), (1, 0), (0.5, 0.8)], radius=0.01)]
    shapes[0].sensor, shapes[1].filter = True, pymunk.ShapeFilter(3, 5, 9)
    constraints = [pymunk.PivotJoint(a, b, (0.1, 0.2), (0.3, 0.4)),
                   pymunk.RotaryLimitJoint(a, b, -0.5, 1.5),
                   pymunk.DampedRotarySpring(a, b, 0.25, 300.0, 12.0),
                   pymunk.GearJoint(a, b, 0.3, 1.0)]
    constraints[3].collide_bodies = False
    index = {a: 0, b: 1}

    def state(obj, part, skip=0):
        return [v for _, v in obj.__getstate__()[part]][skip:]

    body = snapshot._body_record(a)
    mass, moment, body_type = state(a, "init")
    assert _typed(body[:3]) == _typed([body_type, mass, moment])
    assert _typed(body[3]) == _typed(state(a, "general"))
    for s in shapes:
        record = snapshot._shape_record(s, index)
        assert _typed(record[2]) == _typed(state(s, "init", 1)), type(s)
        assert _typed(record[3]) == _typed(state(s, "general")), type(s)
    for c in constraints:
        record = snapshot._constraint_record(c, index)
        assert _typed(record[3]) == _typed(state(c, "init", 2)), type(c)
        assert _typed(record[4]) == _typed(state(c, "general")), type(c)


def test_pymunk_typing_hook_is_gone_only_because_it_only_delegates():
    """puppet.physics drops pymunk's TypingAttrMixing.__setattr__ (a tenth of a
    checkpoint) only when it is the one delegating call; a hook that does more stays."""
    from pymunk._typing_attr import TypingAttrMixing

    from puppet.physics import pymunk_setattr

    assert "__setattr__" not in TypingAttrMixing.__dict__
    assert pymunk_setattr.removed is not None and pymunk_setattr.only_delegates(
        pymunk_setattr.removed)

    class Logging:
        def __setattr__(self, name, value):
            """Logs."""
            print(name)
            super().__setattr__(name, value)

    class Renaming:
        def __setattr__(self, name, value):
            """Renames."""
            super().__setattr__("_" + name, value)

    assert not pymunk_setattr.only_delegates(Logging.__setattr__)
    assert not pymunk_setattr.only_delegates(Renaming.__setattr__)
    assert not pymunk_setattr.only_delegates(None)


def test_a_snapshot_keeps_a_kinematic_body_and_a_one_argument_constraint():
    import pymunk

    from puppet.physics import snapshot

    def build():
        space = pymunk.Space()
        space.gravity = (0, -9.81)
        wheel = pymunk.Body(1.0, 0.5)
        belt = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        belt.angular_velocity = 2.0
        space.add(wheel, belt, pymunk.Circle(wheel, 0.1), pymunk.SimpleMotor(belt, wheel, 3.0))
        return space

    live = build()
    for _ in range(10):
        live.step(0.01)
    copy, _ = snapshot.rebuild(snapshot.capture(live, {}))
    kinds = sorted(b.body_type for b in copy.bodies)
    assert kinds == sorted(b.body_type for b in live.bodies) == [pymunk.Body.DYNAMIC,
                                                                 pymunk.Body.KINEMATIC]
    motor = next(c for c in copy.constraints if isinstance(c, pymunk.SimpleMotor))
    assert motor.rate == 3.0
    for _ in range(50):
        live.step(0.01)
        copy.step(0.01)
    assert [(b.angle, b.angular_velocity) for b in copy.bodies] == \
        [(b.angle, b.angular_velocity) for b in live.bodies]
