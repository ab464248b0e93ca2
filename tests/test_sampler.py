"""The replay's trajectory sampler reads pymunk's C library directly for speed; it
must give the very numbers the plain reading through pymunk's properties gives (the
reference below is the sampler as it was), across rewinds and restores."""

import numpy as np
import pytest

import puppet.timeline.replay as replay_mod
import puppet.timeline.trajectory as trajectory_mod
from puppet.timeline.log import read_log
from puppet.timeline.replay import find_log, replay
from puppet.timeline.trajectory import Sampler


class PlainSampler(Sampler):
    """The reference: every value through pymunk's properties and Character's sensors."""

    def __call__(self, session):
        step = session.steps
        rt = session.runtime
        if rt is not self._runtime:
            self._runtime = rt
            self.state_names.update(dict.fromkeys(rt.spec.states))
            self.mode_names.update(dict.fromkeys(rt.spec.modes))
        if self.rows and step <= self.rows[-1][0]:
            while self.rows and self.rows[-1][0] >= step:
                self.rows.pop()
        c = session.character
        per_link = []
        for name in self.links:
            body = c.bodies[name]
            p = body.local_to_world(body.center_of_gravity)
            low = min(sh.cache_bb().bottom for sh in c.shapes[name])
            per_link.append((p[0], p[1], body.angle, low, c.in_contact(name)))
        servos = [c.servos[j] for j in self.joints]
        self.rows.append((step, session.time, per_link, c.com(), c.root_angle(),
                          [s.angle for s in servos], [s.target for s in servos],
                          [rt.channels.get(j, float("nan")) for j in self.joints],
                          rt.state, rt.mode,
                          trajectory_mod._held(session.sim) if session.sim.grasps else ()))


FIELDS = ("step", "t", "x", "y", "angle", "lowest", "contact", "com", "root_angle",
          "joint_angle", "joint_target", "state", "mode")
# joint_channel holds NaN without channels: compared with NaNs equal
NAN_FIELDS = ("joint_channel",)


# cat-gap (1/240 s) and luxo-gamepad-hop (1/480 s): a sample right after a checkpoint's
# re-seat where a link's first shape's cached box is an ulp off its body's position
# (adding the link's later shapes re-set it); the fast sampler read that box and its
# ``lowest`` differed from the plain one's (head at 12 s in cat-gap, upper_arm at 3 s)
@pytest.mark.parametrize("name", ["luxo-keys-somersaults", "cat-gap", "biped-mocap-walk",
                                  "biped-giant-swings", "luxo-gamepad-hop"])
def test_the_fast_sampler_reads_the_same_numbers_as_the_plain_one(name, monkeypatch):
    log = read_log(find_log(name))  # whole: the leap, the turns over the bar
    fast = replay(log, trajectory=True)
    monkeypatch.setattr(replay_mod, "Sampler", PlainSampler)
    plain = replay(log, trajectory=True)
    assert fast.time == plain.time > 4.0  # (luxo-gamepad-hop: 4.5 s)
    assert fast.final_hash == plain.final_hash
    for field in FIELDS:
        a, b = getattr(fast.trajectory, field), getattr(plain.trajectory, field)
        assert a.shape == b.shape and np.array_equal(a, b), field
    for field in NAN_FIELDS:
        a, b = getattr(fast.trajectory, field), getattr(plain.trajectory, field)
        assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), field
    assert list(fast.trajectory.held) == list(plain.trajectory.held)  # grasps held, per sample
    if name == "biped-giant-swings":  # both hands on the bar
        assert {g[:2] for g in fast.trajectory.held[-1]} == {("hand_near", "bar"),
                                                              ("hand_far", "bar")}
    if name.startswith("biped-mocap"):  # a performance: the joints' channels were read
        assert np.isfinite(fast.trajectory.joint_channel).mean() > 0.9
    assert [str(o) for o in fast.outcomes] == [str(o) for o in plain.outcomes]


def test_the_fast_sampler_follows_a_rewind_and_a_restore():
    """A window-recorded log with a checkpoint and a rewind (fresh bodies after each)."""
    import tempfile
    from pathlib import Path

    from puppet.data.catalog import load_setup
    from puppet.interface import events as ev
    from puppet.session import Session
    from puppet.timeline.log import Recorder

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "rw.jsonl"
        session = Session(load_setup("luxo-mouse"))
        with Recorder(session, path):
            session.handle(ev.mouse(0.9, 0.1))
            session.advance(300)
            session.handle(ev.action("checkpoint"))
            session.handle(ev.mouse(0.1, 0.9))
            session.advance(300)
            session.handle(ev.action("restore"))
            session.advance(200)
            session.handle(ev.action("rewind") | {"to_step": 400})
            session.handle(ev.mouse(0.5, 0.5))
            session.advance(300)
        fast = replay(path, trajectory=True).trajectory
        replay_mod_sampler = replay_mod.Sampler
        try:
            replay_mod.Sampler = PlainSampler
            plain = replay(path, trajectory=True).trajectory
        finally:
            replay_mod.Sampler = replay_mod_sampler
    for field in FIELDS:
        assert np.array_equal(getattr(fast, field), getattr(plain, field)), field
