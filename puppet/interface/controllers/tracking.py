"""Tracking a performance: mocap channels drive the figure (``tracking:`` section).

``angles``: each tracked joint's target is its channel's angle (clamped to the joint's
limits). ``kd`` (Nguyen et al. 2010): the same targets with inertia-scaled gains, and
Cartesian PD pulls of each link's centre of mass toward where the performed pose -
the root channels placing the root joint's hinge, the joint channels bending the rest
- puts it, scaled by ``scale`` (feet strongest, for balance). Three deliberate changes
from the paper's ``u = kp (p* - p) - dp v``: the damping acts on the velocity relative
to the performed one (a walking target is followed without drag), a link's ``scale``
multiplies kp and its square root dp (the damping ratio stays the paper's; a foot
damped 125x would lag the performance by a fifth of a second), and the pull is
integrated implicitly (backward Euler, as a velocity change each control step), so a
foot's 125x gain stays stable at any control rate.

Tracking is an action like any other: a later action that takes a tracked joint
takes it whole - its target, its gains back from KD's, and the pull on the link below
it.

It runs every control period, counted from the performer's last sample: a sample that
comes between two control steps moves them to itself and acts at once (``phase``), so
how closely the figure follows does not hang on when the frames come, nor on the
simulation step (waiting for the next control step, 0-3 steps at 1/480 s, left a 60 Hz
walk's knee 8.4-10.2 deg RMS from the performer's; a stream faster than the control
rate is still followed at that rate). It reads only the channels, the figure's state
and its own plain state, so a replay (or a restored checkpoint) does the same to the
bit. A stream with no sample for ``lost_after`` s is
lost: with ``tracking.stand`` the tracker stands the figure where it is in that pose
(KD control of it, blended in from the last frame); without, it lets go of its joints
(and the figure's gains go back). When samples come again it takes its joints back,
blended over ``tracking.blend``. What it follows at a step is ``_view``: the performer's
channels, the stand, a get-up's poses (``tracking_getup``), or a blend between them.
Impact reactions are ``tracking_reaction``'s.
"""

from __future__ import annotations

import math

from puppet.data.tracking import TrackingSpec
from puppet.interface.controllers.kd_pull import (
    FigureRows,
    inertia_beyond,
    joint_chain,
    lowest_points,
    mix,
)
from puppet.interface.controllers.tracking_contact import IntentionalContacts
from puppet.interface.controllers.tracking_getup import GetUp, joint_degrees
from puppet.interface.controllers.tracking_library import LibraryReactions
from puppet.interface.controllers.tracking_pull import PRESS, TRACK, Pulls
from puppet.interface.controllers.tracking_reaction import Reactions
from puppet.interface.controllers.tracking_walk import WalkInPlace
from puppet.interface.ownership import JointOwners, Owner
from puppet.physics.kinematics import joint_order
from puppet.physics.servo import SET_TARGET as _set_target

__all__ = ["ANGLES", "KD", "OFF", "PRESS", "TRACK", "Tracker"]

OFF, ANGLES, KD = "off", "angles", "kd"


class Tracker(Pulls, Reactions, LibraryReactions, WalkInPlace, IntentionalContacts):
    BUSY = "busy"

    def __init__(self, spec: TrackingSpec | None, character, owners: JointOwners,
                 channels: dict, every: int, dt: float, restore_gains, ground_at=None):
        self.spec = spec
        self.character = character
        self.owners_table = owners
        self.channels = channels  # the runtime's channel values, by bare name
        self.every = every
        self.period = every * dt
        self.dt = dt
        self.restore_gains = restore_gains  # puts the interface's gains back
        self.lost_steps = 0 if spec is None else max(1, round(spec.lost_after / dt))
        self.blend_steps = 0 if spec is None else round(spec.blend / dt)
        self.stand: dict[str, float] | None = None  # channel -> value: tracking.stand's pose
        self.poses: dict[str, dict[str, float]] = {}  # pose -> channels: the get-up's poses
        self.due: list[str] = []  # what the runtime is to run: "lost", "found", "get_up"
        cs = character.spec
        self.order = joint_order(cs)
        self._chain = joint_chain(self.order)  # (the performed pose, kd_pull)
        self.limits = {j.name: (None if j.limits is None else
                                (math.radians(j.limits[0]), math.radians(j.limits[1])))
                       for j in cs.actuated}
        self.joints: dict[str, str] = {}  # tracked joint -> its channel
        if spec is not None:
            names = [j.name for j in cs.actuated] if spec.joints == "all" else spec.joints
            self.joints = {j: spec.channels.get(j, j) for j in names}
        self.inertia = {j: inertia_beyond(character, j) for j in self.joints}
        self.pulled = [link.name for link in cs.links]
        self._figure = FigureRows(character, self.pulled)  # the pulled links, read in bulk
        self.joint_of = {j.child: j.name for j in cs.joints}  # link -> the joint above it
        self.scale = {} if spec is None else dict(spec.scale)
        self.ground_at = ground_at  # x -> the ground's surface height (None: no lift)
        self.soles = {} if spec is None else {f: lowest_points(character, f) for f in spec.feet}
        self._pulls_init()  # (tracking_pull: the compiled kernel's arrays, when it runs)
        self.stop()

    # -- actions ---------------------------------------------------------------------
    def switch(self, mode: str, now: int, blend: bool = True) -> None:
        """``track: off | angles | kd``: start (taking the tracked joints, as any
        action takes the joints it drives, over ``tracking.blend`` s unless ``blend``
        is False: the interface's start) or stop following the performer."""
        if self.mode != OFF and (not self.lost or self.hold is not None):  # (lost: let go
            self._let_go()  # already, unless it stands the figure)
        self.mode = mode
        self.lost = False
        self.hold = self.back = self.getup = None
        self.impact_at = None
        self.reaction = self.step = None
        self.search_at = self.lib = None
        self.prev = None
        self._walk_reset()
        if mode == OFF:
            self.busy = False
            return
        self.kinematic = mode == KD
        self.last_sample = now  # a first sample is awaited for lost_after
        self._take(now, blend)
        self.busy = True

    def set_kinematic(self, how: str) -> None:
        """``kinematic: on | off | toggle``: the Cartesian pulls (off: free fall)."""
        self.kinematic = (not self.kinematic) if how == "toggle" else how == "on"
        self.prev = None
        if not self.kinematic:
            self.impact_at = self.reaction = self.step = None
            self.search_at = self.lib = None

    def sampled(self, now: int) -> bool:
        """A channels frame arrived (the runtime's fast path calls this). True when it
        moved the control steps (``phase``): the runtime is to tick at ``now``."""
        self.last_sample = now
        phase, every = self.phase, self.every
        moved = False
        if now - phase >= every or now < phase:  # (a faster stream: at the control rate)
            moved = (now - phase) % every != 0
            self.phase = now
        if self.lost and self.hold is not None:  # back from standing: blend to the performer
            came = self._view(now)
            self.hold, self.lost = None, False
            self._back_from(came, now)
            self.due.append("found")
        elif self.lost:  # the stream is back: the joints again, blended, and 'found'
            self.lost = False
            self._take(now, True)
            self.due.append("found")
        return moved

    def impact(self, now: int) -> None:
        """A push or a drag has struck the figure: react at the next control step."""
        if self.mode == KD and self.kinematic and self.spec.reaction is not None \
                and not self.lost and self.getup is None:
            self.impact_at = now

    @property
    def status(self) -> str:
        """For the HUD: what tracking does now."""
        if self.mode == OFF:
            return ""
        if self.lost:
            held = ", standing" if self.hold is not None else ""
            return (f"tracking {self.mode}: LOST (no sample for {self.spec.lost_after:g} s)"
                    f"{held}")
        pulls = "" if self.mode == ANGLES else (" with pulls" if self.kinematic else
                                                " (pulls off: free fall)")
        if self.getup is not None:
            pulls += f", getting up ({self.getup.pose_name(self.getup_step)})"
        elif self.reaction is not None and self.mode == KD:
            pulls += f", reacting to a {self.reaction[0]} push{self.library_status()}"
        walking = ", walking in place" if self.walking else ""
        return f"tracking {self.mode}{pulls}{walking}"

    # -- the work ----------------------------------------------------------------------
    def _take(self, now: int, blend: bool = False) -> None:
        mine = [j for j in self.joints if self.joints[j] in self.channels] or list(self.joints)
        self.blend_at = None
        if blend and self.blend_steps > 0:  # from where the joints' targets are now
            servos = self.character.servos
            self.blend_at = now
            self.blend_from = {j: servos[j].target for j in mine}
        self.owners_table.take(mine)
        self.owners_table.claim(mine, TRACK)
        if self.mode == KD:
            self.scale_gains(mine)
        root = self.spec.root
        self.x0 = None
        if root is not None:
            hinge = self._hinge_world()
            x = self._performer(now).get(root.x)
            self.x0 = hinge[0] - (x if x is not None else 0.0)
        self._write_targets(now)

    def _blend(self, step: int) -> float:
        """How far the blend into tracking has come: 0 at its start, 1 when done (and
        without one)."""
        if self.blend_at is None:
            return 1.0
        w = (step - self.blend_at) / self.blend_steps
        if w >= 1.0:
            self.blend_at = None
            self.blend_from = {}
            return 1.0
        return w if w > 0.0 else 0.0

    def scale_gains(self, joints) -> None:
        """KD control's inertia-scaled gains on ``joints`` (remembered, to give back)."""
        preset, servos = self.spec.preset, self.character.servos
        for joint in joints:
            inertia = self.inertia[joint]
            k, d = preset.kq * inertia, preset.dq * inertia
            servos[joint].stiffness, servos[joint].damping = k, d
            self.scaled[joint] = (k, d)

    def _give_back(self, joints) -> None:
        """The interface's gains back on ``joints`` that still have KD's (a key that
        took one and set its own gains keeps those)."""
        servos = self.character.servos
        for joint in joints:
            k, d = self.scaled.pop(joint)
            servo = servos[joint]
            if servo.stiffness == k and servo.damping == d:
                self.restore_gains([joint])

    def _let_go(self) -> None:
        self.owners_table.drop(TRACK)
        self._give_back(list(self.scaled))

    def _hinge_world(self) -> tuple[float, float]:
        joint = self.character.spec.joint(self.spec.root.at)
        body = self.character.bodies[joint.parent]
        p = body.local_to_world(joint.anchor)
        return (p[0], p[1])

    def _start_standing(self, step: int) -> None:
        """Lost: the stand pose where the figure is (the root over the middle of its
        feet, the pelvis upright), blended in from the last frame over ``blend`` s."""
        came = dict(self._view(step))
        held = dict(came)
        held.update(self.stand)
        root = self.spec.root
        if self.soles and self.x0 is not None:
            c = self.character
            middle = sum(c.link_position(f)[0] for f in self.soles) / len(self.soles)
            held[root.x] = middle - self.x0
        held[root.angle] = 0.0
        held[root.clearance] = 0.0
        self.hold = [came, held, step]
        self.prev, self.vel, self.spin = None, {}, {}

    def _start_get_up(self, step: int) -> None:
        """The get-up from where the figure lies (its own joint angles, root place and
        angle), its root kept where it is along the ground."""
        root, c = self.spec.root, self.character
        hx, hy = self._hinge_world()
        if self.x0 is None:
            self.x0 = hx
        came = joint_degrees(c, self.joints)
        came.update({root.x: hx - self.x0, root.y: hy, root.clearance: 0.0,
                     root.angle: math.degrees(c.bodies[c.spec.root].angle)})
        self._getup_from(came, step, hx - self.x0)

    def _getup_from(self, came: dict, step: int, x: float, fresh: bool = True) -> None:
        root = self.spec.root
        self.getup = GetUp(self.spec.reaction.get_up, self.poses, came,
                           (root.x, root.y, root.angle, root.clearance), x, step, self.dt)
        self.getup_x = x
        self.getup_step = step
        if fresh:
            self.prev, self.vel, self.spin = None, {}, {}

    def _back_from(self, came: dict, now: int) -> None:
        """Blend from ``came`` (what was followed) to the performer's frames, the root
        staying where it is (``x0`` taken again, as at a take)."""
        root = self.spec.root
        x = self._performer(now).get(root.x)
        x0 = self.x0
        came = dict(came)
        if x is not None and x0 is not None and root.x in came:
            self.x0 = self._hinge_world()[0] - x
            came[root.x] += x0 - self.x0
        self.back = [came, now]
        self.prev, self.vel, self.spin = None, {}, {}

    def _view(self, step: int) -> dict:
        """The channels followed now: the performer's; while lost and standing, the
        stand blended in from the last frame; getting up, the get-up's poses; back
        from either, the blend from what was followed to the performer's."""
        if self.getup is not None:
            self.getup_step = step
            came = self.getup.view(step)
            if step < self.getup.done_at:
                return came
            self.getup = self.reaction = self.step = None  # up: the performer again
            self._back_from(came, step)
        if self.hold is not None:
            came, held, at = self.hold
            return mix(came, held, self._fraction(step, at))
        if self.lib is not None or self.search_at is not None:  # a motion library's window
            seen = self._library_view(step, self._performer(step))
            if seen is not None:
                return seen
        if self.back is not None:
            came, at = self.back
            w = self._fraction(step, at)
            if w >= 1.0:
                self.back = None
                return self._performer(step)
            return mix(came, self._performer(step), w)
        return self._performer(step)

    def _fraction(self, step: int, at: int) -> float:
        if self.blend_steps <= 0:
            return 1.0
        w = (step - at) / self.blend_steps
        return 1.0 if w >= 1.0 else w if w > 0.0 else 0.0

    def _write_targets(self, step: int) -> dict:
        """The followed channels' joint targets; returns the channels (the pulls of the
        same tick read them again)."""
        table, servos = self.owners_table.table, self.character.servos
        channels = self._view(step)
        w = self._blend(step)
        if w >= 1.0 and self._kern is not None:
            self._write_targets_kernel(self._kern, step, channels)
            return channels
        start, limits, radians = self.blend_from, self.limits, math.radians
        for joint, channel in self.joints.items():
            value = channels.get(channel)
            if value is None or table.get(joint) != TRACK:
                continue
            target = radians(value)
            lim = limits.get(joint)  # _clamped, inlined
            if lim is not None:
                target = lim[0] if target < lim[0] else lim[1] if target > lim[1] else target
            if w < 1.0 and joint in start:  # blending in: part way from where it was
                target = start[joint] + (target - start[joint]) * w
            _set_target(servos[joint].spring._constraint, target)
        return channels

    def _clamped(self, joint: str, q: float) -> float:  # (radians_clamped, for many)
        lim = self.limits.get(joint)
        if lim is None:
            return q
        return lim[0] if q < lim[0] else lim[1] if q > lim[1] else q

    def tick(self, step: int) -> None:
        if (step - self.phase) % self.every or self.mode == OFF:
            return
        self._kernel_tick = None  # (the channels may have changed since)
        if not self.lost and self.getup is None and step - self.last_sample > self.lost_steps:
            self.lost = True
            self.blend_at = self.back = None
            self.due.append("lost")  # the interface's balance takes the figure
            if self.stand is not None and self.mode == KD and self.kinematic \
                    and self.spec.root is not None:
                self._start_standing(step)  # the tracker holds it up: the stand pose
            else:
                self._let_go()
                self.prev = None
                return
        if self.lost and self.hold is None:
            return
        table = self.owners_table.table
        owners = list(map(table.get, self.scaled))
        if owners.count(TRACK) != len(owners):  # joints later actions took: their own
            self._give_back([j for j in self.scaled if table.get(j) != TRACK])  # gains
        if not self.owners_table.holds_any(TRACK):  # every joint taken by later actions
            self.impact_at = None
            return
        channels = self._write_targets(step)
        if self.mode == KD and self.kinematic and self.spec.root is not None:
            self._pull(step, channels)
        else:
            self.impact_at = None
        self._contacts(step)  # a held hand swings the body as the performer's moves

    def next_wakeup(self, earliest: int) -> int | None:
        if self.mode == OFF:
            return None
        phase, every = self.phase, self.every
        return phase - (-(earliest - phase) // every) * every

    def owners(self) -> set[Owner]:
        return {TRACK} if self.mode != OFF else set()

    def get_state(self):
        prev = None if self.prev is None else [
            {n: list(p) for n, p in self.prev.items()}, self.prev_step,
            {n: list(v) for n, v in self.vel.items()}, dict(self.spin)]
        reaction = None if self.reaction is None else list(self.reaction)
        return [self.mode, self.kinematic, self.lost, self.last_sample, self.x0, prev,
                self.impact_at, reaction, {j: list(g) for j, g in self.scaled.items()},
                None if self.step is None else list(self.step),
                [self.blend_at, dict(self.blend_from),
                 None if self.getup is None else [*self.getup.state(), self.getup_x],
                 list(self.due),
                 None if self.hold is None else [dict(self.hold[0]), dict(self.hold[1]),
                                                 self.hold[2]],
                 None if self.back is None else [dict(self.back[0]), self.back[1]],
                 self.library_state(), self.walk_state(), self.contacts_state(),
                 self.phase]]

    def set_state(self, state) -> None:
        (self.mode, self.kinematic, self.lost, self.last_sample, self.x0, prev,
         self.impact_at, reaction, scaled, step) = state[:10]
        more = state[10] if len(state) > 10 else [None, {}, False, [], None, None]
        self.blend_at, self.blend_from = more[0], dict(more[1])
        self.getup = None
        if more[2] is not None:
            self._getup_from(dict(more[2][0]), more[2][1], more[2][2], fresh=False)
        self.due = list(more[3])  # (older snapshots have none of these)
        self.hold = None if more[4] is None else [dict(more[4][0]), dict(more[4][1]),
                                                  more[4][2]]
        self.back = None if more[5] is None else [dict(more[5][0]), more[5][1]]
        self.set_library_state(more[6] if len(more) > 6 else [None, None, 0])
        self.set_walk_state(more[7] if len(more) > 7 else None)
        self.set_contacts_state(more[8] if len(more) > 8 else None)
        self.phase = more[9] if len(more) > 9 else 0
        self.step = None if step is None else list(step)
        self.scaled = {j: tuple(g) for j, g in scaled.items()}
        self.reaction = None if reaction is None else tuple(reaction)
        self.prev, self.prev_step, self.vel, self.spin = None, -1, {}, {}
        if prev is not None:
            self.prev = {n: tuple(p) for n, p in prev[0].items()}
            self.prev_step = prev[1]
            self.vel = {n: tuple(v) for n, v in prev[2].items()}
            self.spin = dict(prev[3])
        self.busy = self.mode != OFF

    def adopt(self, old: Tracker, same, now: int) -> set[Owner]:
        if old.mode != OFF and self.spec is not None and same("tracking", ""):
            self.set_state(old.get_state())
            return {TRACK}
        if old.scaled:  # tracking ends with the old file: the joints' own gains back
            self.restore_gains(list(old.scaled))
        return set()

    def stop(self) -> None:
        self.mode = OFF
        self.kinematic = False
        self.lost = False
        self.last_sample = 0
        # the control steps are the steps phase + n * every: a performer's sample that
        # comes between two moves them to itself (``sampled``), so it acts at once
        self.phase = 0
        self.x0 = None
        self.prev = None  # the performed link positions at the last sample
        self.prev_step = -1  # ... the step that sample came at
        self.vel: dict = {}  # ... and their velocities from the two last samples
        self.spin: dict = {}  # ... and the feet's turning rates
        self.scaled: dict[str, tuple[float, float]] = {}  # joint -> KD gains it was given
        self.impact_at: int | None = None  # a push to judge at the next control step
        self.reaction: tuple[str, int] | None = None  # (case, step it began)
        self.step: list | None = None  # a large push's protective step (_protective_step)
        self.blend_at: int | None = None  # the step a blend into tracking began
        self.blend_from: dict[str, float] = {}  # ... the joints' targets then
        self.getup: GetUp | None = None  # after a fall: the get-up under way
        self.getup_x = 0.0  # ... the root's travel it keeps
        self.getup_step = 0  # ... the step last followed (the HUD's pose)
        self.hold: list | None = None  # lost, standing: [channels then, the stand's, step]
        self.back: list | None = None  # back from standing: [channels followed, step]
        self.search_at: int | None = None  # a library search due at this step
        self.lib: list | None = None  # a library window followed: [index, step, x offset]
        self.searches = 0  # library searches made (tests read it)
        self._walk_reset()  # walking in place (tracking_walk)
        self._contacts_reset()  # intentional contacts (tracking_contact)
        self.due = []
        self.busy = False

