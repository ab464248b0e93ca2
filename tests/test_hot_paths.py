"""The hot paths made faster for the bench give what the plain paths give: the channel
frames kept until the next flush and the inline clamped linear map."""

from __future__ import annotations

import math

import pytest

from puppet.commands.bench.channels import channel_interface_text
from puppet.data.catalog import load_character_named, load_setup, setup_from_text
from puppet.interface import events as ev
from puppet.interface import maps as mapping
from puppet.session import Session


def _setup(tmp_path):
    cat, _ = load_character_named("cat")
    path = tmp_path / "channels.yaml"
    path.write_text(channel_interface_text(cat, "cat-flat", count=6))
    return load_setup(str(path))


def test_channel_frames_of_other_names_at_one_step_are_stored_in_their_order(tmp_path):
    session = Session(_setup(tmp_path))
    frames = [{"c0": 0.5, "c1": -0.5}, {"c2": 0.25}, {"c0": -0.75, "c1": 0.1},
              {"c0": 0.3, "c1": 0.9}, {"x": 2.0}]
    for values in frames:
        session.handle(ev.channels(values))
    assert session.runtime.channels == {}  # kept until the next flush...
    session.runtime.flush()
    want: dict = {}
    for values in frames:
        want.update(values)
    assert session.runtime.channels == want  # ...then the last value of each name
    servos = session.character.servos
    alone = Session(_setup(tmp_path))
    alone.handle(ev.channels(want))
    alone.runtime.flush()
    assert [s.target for s in servos.values()] == \
        [s.target for s in alone.character.servos.values()]
    session.advance(40)
    alone.advance(40)
    assert session.sim.state_hash() == alone.sim.state_hash()


def test_a_hot_reload_keeps_the_channel_values_not_yet_flushed(tmp_path):
    setup = _setup(tmp_path)
    session = Session(setup)
    old = session.runtime
    old._on_channels({"c3": 0.6})  # straight to the runtime: nothing flushes it
    session.reload((tmp_path / "channels.yaml").read_text())
    assert session.runtime is not old
    assert session.runtime.read_input("channel.c3") == 0.6


def test_the_compiled_maps_give_the_plain_formulas_bits():
    text = ("name: t\ndescription: t\ncharacter: luxo\nmaps:\n"
            "  - {input: mouse.x, joint: ankle, from: [0.1, 0.9], to: [80, -75.3]}\n"
            "  - {input: channel.k, joint: knee, from: [-1, 1.5], to: [-17, 133]}\n"
            "  - {input: mouse.y, joint: knee, to: [150, 0], curve: {power: 0.66}}\n"
            "  - {input: channel.s, joint: ankle, from: [0, 2], to: [30, -80],"
            " curve: smoothstep}\n"
            "  - {input: mouse.x, joints: {ankle: -0.5}, from: [0.2, 0.7], to: [10, 40],"
            " clamp: false, curve: {power: 2}}\n")
    setup = setup_from_text(text, "t.yaml")
    session = Session(setup)
    servos = session.character.servos
    channels: dict = {}
    for m in setup.interface.maps:
        fast = mapping.compile_map(m, servos, {}, channels)
        (x0, x1), (y0, y1) = m.from_, m.to
        for v in (-3.0, -1.0, 0.0, 0.1, 0.37, 0.9, 1.2, 1.5, 1e6, math.nan):
            channels[m.input.removeprefix("channel.")] = v
            fast({m.input: v})
            u = (v - x0) * (1.0 / (x1 - x0))
            if m.clamp:
                u = 0.0 if u < 0.0 else 1.0 if u > 1.0 else u
            value = math.radians(y0) + mapping.shape(m.curve, u) * math.radians(y1 - y0)
            for joint, gain in m.gains().items():
                got, want = servos[joint].target, gain * value
                assert got == want or (math.isnan(got) and math.isnan(want)), (m, v)


def test_fused_channel_maps_write_what_the_maps_one_by_one_write():
    """maps.fused folds runs of plain maps into one loop: the same targets (bits), the
    same joints written, in order, around a curved map that breaks the run and with
    an input missing."""
    text = ("name: t\ndescription: t\ncharacter: biped\nscene: flat\nmaps:\n"
            "  - {input: channel.a, joint: hip_near, from: [-1, 1], to: [-30, 40]}\n"
            "  - {input: channel.b, joint: knee_near, from: [0, 2], to: [-5, 90]}\n"
            "  - {input: channel.a, joint: hip_far, to: [10, -20], curve: smoothstep}\n"
            "  - {input: channel.c, joint: knee_far, from: [-1, 1], to: [0, 120]}\n"
            "  - {input: channel.b, joint: ankle_far, from: [-1, 1], to: [-20, 20]}\n"
            "  - {input: channel.a, joint: ankle_near, from: [1, -1], to: [-25, 35]}\n")
    setup = setup_from_text(text, "t.yaml")
    plain, fast = Session(setup), Session(setup)
    appliers = {}
    for session in (plain, fast):
        rt = session.runtime
        appliers[session] = [mapping.compile_map(m, session.character.servos, {},
                                                 rt.channels) for m in setup.interface.maps]
    folded = mapping.fused(appliers[fast])
    assert len(folded) == 3  # [a, b] [curved] [c, b, a]
    for values in ({"a": 0.3, "b": 1.7, "c": -0.2}, {"a": -4.0, "c": 2.5},
                   {"b": 0.11}, {"a": 0.999, "b": -1e9, "c": 0.5}):
        got, want = [], []
        for session, run, out in ((plain, appliers[plain], want), (fast, folded, got)):
            session.runtime.channels.update(values)
            for apply in run:
                out += list(apply(session.runtime.inputs))
        assert got == want, values
        assert [s.target for s in fast.character.servos.values()] == \
            [s.target for s in plain.character.servos.values()], values


def test_fused_grids_write_what_the_grids_one_by_one_write():
    """maps.fused folds a run of full grids on the same inputs (the cat's four legs,
    two mirrors) into one applier: the same targets to the bit and the same joints,
    for inputs in and out of range and with an input missing; grids sharing a joint
    are left apart."""
    import random

    from puppet.data.interfaces import GridMapSpec
    from puppet.interface.active_maps import every_map

    setup = load_setup("cat-trot")
    plain, fast = Session(setup), Session(setup)
    appliers = {}
    for session in (plain, fast):
        rt = session.runtime
        grids = [m for m in every_map(rt.spec) if isinstance(m, GridMapSpec)]
        appliers[session] = [mapping.compile_map(m, session.character.servos,
                                                 rt.pose_targets) for m in grids]
    folded = mapping.fused(appliers[fast])
    assert len(appliers[fast]) == 4 and len(folded) == 1
    assert len(mapping.fused(appliers[fast][:1] * 2)) == 2  # the same joints twice
    rng = random.Random(3)
    inputs = [{"mouse.x": 0.0, "mouse.y": 0.0}, {"mouse.x": 1.0, "mouse.y": 1.0},
              {"mouse.x": 0.5}, {"mouse.x": -0.3, "mouse.y": 1.4}] + [
        {"mouse.x": rng.uniform(-0.2, 1.2), "mouse.y": rng.uniform(-0.2, 1.2)}
        for _ in range(200)]
    for values in inputs:
        got, want = [], []
        for run, out in ((appliers[plain], want), (folded, got)):
            for apply in run:
                out += list(apply(values))
        assert got == want, values
        assert [s.target for s in fast.character.servos.values()] == \
            [s.target for s in plain.character.servos.values()], values


def _checked_ticks(session):
    """Wrap the runtime's tick: after each, the schedule it kept (the WAITED shortcut)
    must be the one a full reschedule computes; the run then goes on with the kept
    schedule (the production path, stale wake-ups and all). ``kept`` counts the ticks
    that really took the shortcut (no reschedule inside the tick). The ticks are
    Python's: the kernel's stepping loop (``interface.poll_plan``), which does the
    same work between them, is left out here (tests/test_kernel_poll.py compares it
    with these ticks)."""
    runtime = session.runtime
    runtime.poll = None
    tick, reschedule = runtime.tick, runtime._reschedule
    seen = {"ticks": 0, "kept": 0, "in_tick": False, "rescheduled": False}

    def spy(*args, **kwargs):
        if seen["in_tick"]:
            seen["rescheduled"] = True
        return reschedule(*args, **kwargs)

    def checked(step):
        seen["in_tick"], seen["rescheduled"] = True, False
        tick(step)
        seen["in_tick"] = False
        kept = (runtime.next_wakeup, list(runtime._active), runtime._controllers_wake)
        reschedule(step + 1)
        assert (runtime.next_wakeup, list(runtime._active)) == kept[:2], step
        runtime.next_wakeup, runtime._active, runtime._controllers_wake = kept
        seen["ticks"] += 1
        seen["kept"] += not seen["rescheduled"]
    runtime.tick, runtime._reschedule = checked, spy
    return seen


def test_a_tick_that_only_waited_keeps_the_schedule_a_full_reschedule_gives():
    from puppet.commands.bench.subjects import gesture
    from puppet.data.catalog import load_setup

    # luxo-keys: 13 s of key taps, a key a second (sequences, then poses that take a
    # running sequence's joints), its state machine polled every frame; biped-step:
    # feedback maps and frame targets at the control rate
    for name, frames in (("luxo-keys", 800), ("biped-step", 150)):
        setup = load_setup(name)
        session = Session(setup, keyframes=False)
        seen = _checked_ticks(session)
        for batch in gesture(frames, setup.interface):
            for event in batch:
                session.handle(event)
            for _ in range(8):
                session.advance(1)
        # (biped-step's feedback ticks write at each control step: no shortcut taken,
        # its schedule is still checked at every tick)
        assert seen["ticks"] > 100 and seen["kept"] > (10 if name == "luxo-keys" else -1), \
            (name, seen)


def test_every_step_blends_and_sensor_maps_keep_the_schedule_a_full_reschedule_gives():
    """Luxo's helpers at ``control_rate: 480``: a blend writing plain targets and sensor
    maps, each at every step, only wait as far as the schedule goes (base.WAITED); the
    replays keep their hashes and every kept schedule is the full one."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    for name in ("luxo-shuffle", "luxo-back-headspring", "luxo-double-backflip",
                 "biped-kip", "biped-handstand", "biped-backflip"):
        log = read_log(f"assets/logs/{name}.jsonl")
        session = new_session(log, setup_for_log(log)[0])
        seen = _checked_ticks(session)
        LogFeeder(session, log).advance(log.last_step)
        assert session.sim.state_hash() == log.end_hash, name
        assert seen["ticks"] > 300 and seen["kept"] > 100, (name, seen)


@pytest.mark.parametrize("name", ["biped-ladder-climb", "biped-monkey-bars",
                                  "biped-gymnast-climb-bound", "biped-gymnast-climb-trot"])
def test_climbs_ticks_that_only_wait_keep_the_schedule_a_full_reschedule_gives(name):
    """A reach's tick that only wrote its chain's targets (no reach ended, no grasp made)
    and an armed grasp's try that caught nothing (the gymnast's feet, armed at every
    step) only wait (base.WAITED): the climbs keep their hashes, most of their ticks keep
    the schedule and every kept schedule is the full one."""
    from puppet.timeline.log import read_log
    from puppet.timeline.replay import LogFeeder, new_session, setup_for_log

    log = read_log(f"assets/logs/{name}.jsonl")
    session = new_session(log, setup_for_log(log)[0])
    seen = _checked_ticks(session)
    LogFeeder(session, log).advance(log.last_step)
    assert session.sim.state_hash() == log.end_hash, name
    assert seen["ticks"] > 1000 and seen["kept"] > seen["ticks"] // 2, (name, seen)


def test_a_sensor_map_holding_a_frame_target_every_step_keeps_the_frames_scheduled(tmp_path):
    """A state's sensor map with ``frame: world`` at ``control_rate: 480``: the feedback
    tick only waits, but the frame target it held must be re-solved, so the arbiter
    reschedules (the kept schedule would leave the frame controller out)."""
    import re

    with open("interfaces/biped-balance.yaml") as f:
        text = f.read().replace("name: biped-balance", "name: biped-fbframe")
    text = re.sub(r"joints: \{waist: \{world: 0\}.*?elbow_far: 12\}",
                  "joints: {neck: 0, hip_near: 0, knee_near: -10, ankle_near: -5, "
                  "hip_far: 0, knee_far: -10, ankle_far: -5, shoulder_near: -6, "
                  "elbow_near: 12, shoulder_far: 6, elbow_far: 12}", text, flags=re.S)
    text = re.sub(r"  - \{input: mouse.y, joints: \{ankle_near.*?knees bend\}\n", "", text,
                  flags=re.S)
    text = re.sub(r"  - \{input: mouse.x, joint: waist.*?\(right = forward\)\}\n", "", text,
                  flags=re.S)
    text = text.replace("slowdown: 1\n", "slowdown: 1\ncontrol_rate: 480\n")
    text = text.replace("    enter: {pose: stand}\n", "    enter: {pose: stand}\n    maps:\n"
                        "      - {input: sensor.com.vx, joint: waist, from: [-1, 1], "
                        "to: [10, -10], frame: world}\n")
    assert "frame: world}" in text and "control_rate: 480" in text
    path = tmp_path / "biped-fbframe.yaml"
    path.write_text(text)
    session = Session(load_setup(str(path)), keyframes=False)
    assert session.runtime.feedback.every == 1
    seen = _checked_ticks(session)
    session.advance(400)
    assert session.runtime.frames.held and seen["ticks"] > 300, seen


def test_advance_steps_chipmunk_itself_exactly_when_step_space_would():
    """The stepping loop calls cpSpaceStep itself when ``clean``: nothing queued in
    pymunk's space (step_space's own test) and no shape to let go of after a step."""
    import pymunk

    from puppet.physics.simulation import queued
    from puppet.session.stepping import clean as _clean

    space = pymunk.Space()
    assert _clean(space) and not queued(space)
    body = pymunk.Body(1.0, 1.0)
    shape = pymunk.Circle(body, 0.1)
    space.add(body, shape)  # a body to check at the next step
    assert not _clean(space) and queued(space)
    space.step(0.01)
    assert _clean(space) and not queued(space)
    space.remove(shape)  # a shape to let go of after a step
    assert not _clean(space) and not queued(space) and space._removed_shapes
    space.add_post_step_callback(lambda *a: None, "k")
    assert not _clean(space) and queued(space)


def test_a_one_sensor_state_polls_as_the_general_loop_does():
    from puppet.data.catalog import load_setup

    session = Session(load_setup("luxo-keys"), keyframes=False)
    machine = session.runtime.machines["main"]
    assert machine.current == "upright" and machine._one_sensor is not None
    root = session.character.bodies[session.character.spec.root]
    fast = machine._one_sensor
    for degrees in (-179.0, -100.5, -100.0, -99.0, 0.0, 99.9, 100.0, 100.01, 170.0, 181.0):
        root.angle = math.radians(degrees)
        for step in (0, 8, 16, 19):  # polled steps and one between polls
            machine._one_sensor = fast
            got = (machine.due(step), getattr(machine, "wake_after", None))
            machine._one_sensor = None  # the general loop
            want = machine.due(step)
            assert got[0] == want, (degrees, step)
            if want is None and step % machine.every == 0:
                assert got[1] == machine.next_wakeup(step + 1)
            machine.wake_after = None
    machine._one_sensor = fast


def test_a_state_left_by_an_immediate_timer_alone_is_not_a_one_sensor_state(tmp_path):
    """A state whose only transition is `{to: X, after: 0}` reads no sensor: it takes the
    general loop (it used to be taken for a one-sensor state and call a missing reader)."""
    from puppet.data.catalog import load_setup

    iface = tmp_path / "timer.yaml"
    iface.write_text(
        "name: timer\ndescription: an immediate timer\ncharacter: luxo\nscene: flat\n"
        "keys:\n  - {key: g, goto: passing}\ninitial: resting\nstates:\n  resting: {}\n"
        "  passing:\n    transitions:\n      - {to: done, after: 0}\n  done: {}\n",
        encoding="utf-8")
    session = Session(load_setup(str(iface)), keyframes=False)
    session.handle({"type": "key", "key": "g", "down": True})
    session.advance(2)
    machine = session.runtime.machines["main"]
    assert machine.current == "done" and machine._one_sensor is None


def test_a_process_imports_only_what_its_command_needs():
    """Process start: --version imports no models, a character's check no interface
    models, a plain replay neither numpy nor the expectations (a fresh interpreter);
    pydantic never (msgspec validates)."""
    import subprocess
    import sys

    from puppet.data.catalog import ROOT

    probe = ("import sys, contextlib, io\n"
             "from puppet.commands import main\n"
             "with contextlib.redirect_stdout(io.StringIO()):\n"
             "    try:\n"
             "        main(sys.argv[1:])\n"
             "    except SystemExit:\n"
             "        pass\n"
             "print(' '.join(m for m in ('pydantic', 'msgspec', 'numpy', 'pygame',"
             " 'puppet.data.interfaces', 'puppet.timeline.expectations')"
             " if m in sys.modules))\n")

    def loaded(*args):
        out = subprocess.run([sys.executable, "-c", probe, *args], cwd=ROOT, check=True,
                             capture_output=True, text=True).stdout.split()
        return set(out)

    assert loaded("--version") == set()
    assert loaded("check", "characters/luxo.yaml") == {"msgspec"}
    assert loaded("replay", "luxo-hop", "--headless") == {"msgspec", "puppet.data.interfaces"}
    checked = loaded("replay", "luxo-hop", "--headless", "--check")
    assert "numpy" in checked and "pydantic" not in checked


def test_the_space_stepped_in_c_is_the_space_stepped_by_pymunk():
    """step_space calls Chipmunk's step itself: the same bits as pymunk's Space.step,
    also across a body added between steps (which takes pymunk's own step, for its
    mass check) and a grasp pin added and removed."""
    import pymunk

    from puppet.physics.simulation import step_space

    def run(stepper):
        s = Session(load_setup("luxo-mouse"))
        sim = s.sim
        s.handle(ev.mouse(0.9, 0.2))
        stepper(sim.space, sim.dt, 300)
        ball = pymunk.Body(0.5, pymunk.moment_for_circle(0.5, 0, 0.03))
        ball.position = (0.2, 0.6)
        sim.space.add(ball, pymunk.Circle(ball, 0.03))
        assert sim.space._bodies_to_check
        stepper(sim.space, sim.dt, 200)
        pin = pymunk.PivotJoint(sim.space.static_body, sim.character.bodies["base"],
                                tuple(sim.character.bodies["base"].position))
        sim.space.add(pin)
        stepper(sim.space, sim.dt, 100)
        sim.space.remove(pin)
        stepper(sim.space, sim.dt, 100)
        return [(tuple(b.position), b.angle, tuple(b.velocity)) for b in sim.space.bodies]

    def pymunks(space, dt, n):
        for _ in range(n):
            space.step(dt)

    assert run(step_space) == run(pymunks)


def _support_by_pymunk(character):
    """support_extent through pymunk's own objects (arbiter.contact_point_set)."""
    from puppet.physics.snapshot import restored_contacts

    xs = []
    for body in character.bodies.values():
        restored = restored_contacts(body)
        if restored is not None:
            xs += [x for x, _ in restored]
        else:
            body.each_arbiter(lambda a, xs=xs: xs.extend(p.point_a.x
                                                         for p in a.contact_point_set.points))
    return (min(xs), max(xs)) if xs else None


def test_the_support_extent_read_through_c_is_pymunks():
    """Character.support_extent reads the contact points with Chipmunk's call and the
    restored contacts once per space: the same extent as pymunk's objects give, while
    walking, lying and right after a checkpoint re-seats the space."""
    from puppet.commands.bench.subjects import Subject, gesture

    subject = Subject("biped", "biped-floor")
    session = subject.session(keyframes=False)
    frames = gesture(subject.frames(6.0), subject.interface_spec)
    seen = {"none": 0, "some": 0, "restored": 0}
    for k, batch in enumerate(frames):
        for event in batch:
            session.handle(event)
        session.advance(subject.steps_per_frame)
        if k % 45 == 0:
            session.sim.checkpoint()  # the next reading is from the restored contacts
            seen["restored"] += 1
        c = session.character
        got, want = c.support_extent(), _support_by_pymunk(c)
        assert got == want, k
        seen["none" if got is None else "some"] += 1
    assert seen["some"] > 100 and seen["restored"] > 5


def test_sampled_sensors_share_one_centre_of_mass_and_only_while_sampling():
    """Character.sample works the centre of mass out once for all readers (kip's two
    com.dx maps): the values are the plain reads', and after it com() reads afresh."""
    from puppet.interface.conditions import map_reader

    session = Session(load_setup("biped-kip"))
    session.advance(30)
    c = session.character
    names = ["com.dx.foot_near", "com.dx.foot_far", "com.vx", "com.x"]
    readers = [(n, map_reader(n, c)) for n in names]
    plain = {n: read() for n, read in readers}
    calls = []
    compute = c._com
    c._com = lambda: calls.append(1) or compute()
    sampled: dict = {}
    c.sample(readers, sampled)
    assert sampled == plain and len(calls) == 1
    before = c.com()
    session.advance(8)
    assert c.com() != before and len(calls) == 3  # no memo outside sample
