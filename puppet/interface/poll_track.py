"""A tracker following the performer's angles beside state machines, in ``pk_poll``.

``PollPlan`` (one machine or several) gave up whenever a tracker was on: an
interface that tracks a performer's arms while a state machine walks the legs
(biped-walk's ``track: angles``), or whose machines only hold the grasps, ticked in
Python at every control step, and its mouse moves were Python's too. A tracker in
``angles`` mode does little at a control step (``Tracker.tick``): each tracked
joint's target is its channel's angle, in radians, clamped to the joint's limits
(``_write_targets``), where the tracker still owns the joint; between two samples
the channels are the same and so are the targets. That is ``pk_targets`` (the KD
tracker's, ``kernel_source``) on rows of the tracked joints alone, which ``pk_poll``
runs at the tracker's control steps (``t_phase + n * t_every``) before the machine's
blends, frame targets and sensor maps, in ``InterfaceRuntime._watched``'s order.

``AngleTrack.fill`` puts it in the plan when that is all the tracker has to do: the
mode ``angles``, not lost and no blend into tracking under way, nothing ``due``, no
walk in place, the tracker still holding a joint (and, without intentional contacts,
only with ``ANGLES_ALONE``, below); ``pk_tick`` stops at the first tracker tick that
finds the stream lost (``t_lost``). In a replay a sample is one of the events of the
kernel's runs (``session.event_runs``' SAMPLE, ``pk_sample``: the values stored, the
tracker's last sample and phase moved as ``Tracker.sampled`` moves them, handed back
by ``handed_back``), so a run goes on across samples; else the run stops at it and
the tick there may be the kernel's (``PollPlan.resume``, the plan filled again).

Intentional contacts (``tracking.contacts``, the high bar's) are the tracker's too:
``kernel_poll_contact.pk_contacts`` after the targets, on rows of each held hand
(its grasp's pin, the contact's start, the performer's vector and rates, which
Python works out at the sample when the tick there is the kernel's, as its tick
would first). A contact that begins or ends is Python's. Python's tick polls the
machines after the controllers (the tracker's contacts among them), ``pk_tick``
before them: when a machine reads a sensor the contacts move (``VELOCITY``), the plan
says ``c_late`` and the kernel makes a tracker tick's contacts first, undone (the
velocities saved) when the tick is Python's after all; a sequence's ``until``, polled
before the contacts in both, reading one too: Python's. Without the kernel there
is no plan: the same ticks run in Python, to the same bits (tests/test_poll_track.py).
"""

from __future__ import annotations

from puppet.interface.controllers import feedback_kernel as _fk
from puppet.interface.controllers.tracking import ANGLES
from puppet.interface.controllers.tracking_pull import TRACK
from puppet.interface.poll_table import NEVER

# The sensors ``pk_contacts``' velocity change moves (every body's velocity by the same
# step: the centre of mass's velocity, the fall time from it, the body's spin about it,
# equal in exact arithmetic but not in floating point). A link's spin (its angular
# velocity), place, angle, height, contact and the centre of mass's place and offsets
# are not written between the machines' polls and Python's (the rest of ``pk_tick``
# writes servo targets: reaches, tracked joints, blends, frame targets, feedback; a
# grasp made stops the run; ``pk_track_pull``, which sets velocities and spins, is
# ``TrackPoll``'s alone, with no machines).
VELOCITY = frozenset((_fk.COM_VX, _fk.COM_VY, _fk.FALL_TIME, _fk.COM_SPIN))

# An angles tracker with no contacts beside a machine (biped-walk's mocap arms): with a
# run stopping at each sample its Python tick (about 16 us) cost no more than
# ``PollPlan.ready`` and ``run`` around the kernel's (13-14 us and 5 us: 37 % overhead
# against 42 %), so it was Python's; with the samples inside the runs (pk_sample) the
# kernel's is the cheaper (36 -> 22-26 %, biped-walk-mocap-arms, docs/benchmarks.md).
ANGLES_ALONE = True

SAMPLE = -2  # a performer's sample among a run's events (its kind: PK_EV_SAMPLE)


class AngleTrack:
    """``pk_targets``' rows of one tracker's joints, and its part of a ``PollPlan``."""

    def __init__(self, plan):
        self.poll = plan
        ffi = self.ffi = plan.ffi
        tr = self.tracker = plan.runtime.tracker
        self.joints = list(tr.joints)  # (Tracker.joints' order: _write_targets')
        self.names = list(dict.fromkeys(tr.joints[j] for j in self.joints))
        self.key = tuple(self.names)  # (a sample's values in this order: event_runs;
        self._hands: tuple = ()  # the contacts' hands after them: _contacts)
        place = {name: i for i, name in enumerate(self.names)}
        n, m = max(1, len(self.names)), max(1, len(self.joints))
        self.t = t = ffi.new("pk_track *")
        self._keep = keep = [ffi.new("int[]", [place[tr.joints[j]] for j in self.joints] or 1),
                             ffi.new("int[]", [tr.limits.get(j) is not None
                                               for j in self.joints] or 1),
                             ffi.new("double[]", [(tr.limits.get(j) or (0.0, 0.0))[0]
                                                  for j in self.joints] or 1),
                             ffi.new("double[]", [(tr.limits.get(j) or (0.0, 0.0))[1]
                                                  for j in self.joints] or 1),
                             ffi.new("void *[]", m)]
        t.n_targets = len(self.joints)
        t.target_value, t.target_limited, t.target_lo, t.target_hi, t.spring = keep
        self._vals, self._has = ffi.new("double[]", n), ffi.new("char[]", n)
        self._own = ffi.new("char[]", m)
        self._springs_of = None  # (the bodies the springs were bound with: a re-seat
        # binds the servos to new springs, Character.bind, and makes new bodies)
        self._on = False  # (the plan's track is this one's: set once, until cleared)
        self._has_on = self._own_was = self._phase_was = None  # (as the plan has them)
        self._c_body, self._c_row = ffi.new("void *[4]"), ffi.new("double[40]")
        self._pins: list = []  # (the grasps' pins the rows are of)
        self._anchors: dict = {}  # (a pin's anchor: set when it is made, or re-seated)
        self._sim = self._seat = None  # (the sim and its seats the two are of: a restore re-seats
        # in place, the same pin objects taking the snapshot's anchors)
        self._com_of = self._com_args = None  # (the bodies the plan's com rows are of)

    def _bind(self, character) -> None:
        spring, servos = self.t.spring, character.servos
        for j, joint in enumerate(self.joints):
            spring[j] = self.poll.pointer(servos[joint].spring._constraint)
        self._springs_of = character.bodies

    def fill(self, step: int, resume: bool) -> int | None:
        """The tracker's part of the plan (after the rest of ``PollPlan.ready``): the
        step the run must stop at (the first control step its stream is lost at), or
        None when its tick is not all ``pk_targets``' to do. ``resume``: the tick at
        ``step`` may be the kernel's (the sample there stored first)."""
        tr, rt = self.tracker, self.poll.runtime  # (may_track said yes: ready's start)
        owners = rt.owners
        if not owners.holds_any(TRACK):  # (Tracker.tick returns: nothing to write)
            return None
        phase, every = tr.phase, tr.every
        if resume and (step - phase) % every == 0 \
                and step - tr.last_sample > tr.lost_steps:  # (lost there: Python's)
            return None
        p, ffi = self.poll.plan, self.ffi
        p.c_n, p.ch_t = 0, len(self.names)
        if tr.spec.contacts is not None and tr.held_points is not None \
                and not self._contacts(tr, rt, p, resume and (step - phase) % every == 0,
                                       step):
            return None
        if tr.character.bodies is not self._springs_of:
            self._bind(tr.character)
        if not self._on:  # (the plan's track part as this plan has it: kept until
            p.track, p.t_vals, p.t_nopull, p.t_pose = self.t, self._vals, 1, 0  # cleared)
            p.walk, p.t_mix, p.g_on, p.l_on, p.rx_on, p.st_on = ffi.NULL, 0, 0, 0, 0, 0
            self._on, self._has_on, self._own_was, self._phase_was = True, None, False, None
        got = list(map(tr.channels.get, self.names))  # (_performer: the channels)
        k = len(got)
        if None in got:
            self._has[0:k] = bytes(v is not None for v in got)
            self._vals[0:k] = [0.0 if v is None else v for v in got]
            if not self._has_on:
                p.t_has, self._has_on = self._has, True
        else:
            self._vals[0:k] = got
            if self._has_on is not False:
                p.t_has, self._has_on = ffi.NULL, False
        own = tr._owned(owners.table, self.joints, "_every_angle")
        if own != self._own_was:
            if own is None:
                p.t_own = ffi.NULL
            else:
                self._own[0:len(own)] = own
                p.t_own = self._own
            self._own_was = own
        if (phase, every) != self._phase_was:
            p.t_phase, p.t_every, self._phase_was = phase, every, (phase, every)
        # the first control step whose tick finds the stream lost is Python's: pk_tick
        # stops there (samples the run applies move it on: pk_sample)
        p.t_lost, p.t_sample = tr.lost_steps, tr.last_sample
        return NEVER

    def handed_back(self) -> None:
        """After a run that applied samples (``pk_sample``) or swung the figure by its
        contacts: the tracker's last sample and phase as ``Tracker.sampled`` left them
        (the values: ``EventRuns.applied``), each contact's performer rates as
        ``_performer_rate`` left them (``pk_contact_rates``)."""
        p, tr = self.poll.plan, self.tracker
        tr.last_sample, tr.phase = p.t_sample, p.t_phase
        self._phase_was = (p.t_phase, p.t_every)
        if p.c_n:
            perf, row, sv, seen = tr.perf_turn, self._c_row, p.c_sv, p.c_seen
            for j, channel in enumerate(self._hands):
                if seen[j] > perf[channel][2]:
                    perf[channel] = [sv[2 * j], sv[2 * j + 1], seen[j], row[10 * j + 8],
                                     row[10 * j + 9]]

    def _contacts(self, tr, rt, p, first: bool, step: int) -> bool:
        """Intentional contacts' rows (``IntentionalContacts._contacts``) into the plan:
        each held hand with the performer's vector, its contact begun; the performer's
        rates worked out here when a sample came since and the tick at ``step`` is the
        kernel's (``first``: what Python's tick there does first, and again to no
        effect if it runs after all); False when a contact begins or ends (Python's)."""
        sim = rt.sim
        spec, grasps = tr.spec.contacts, sim.grasps
        if sim.seats != self._seat or sim is not self._sim:
            self._sim, self._seat = sim, sim.seats
            self._anchors.clear()
            self._pins = []
        chains, contact, perf = rt.grasping.chains, tr.contact, tr.perf_turn
        row, pins, vector = [], [], tr._performer_vector
        hands, seen_at, seen_step, xy, get = [], [], [], [], tr.channels.get
        for chain, channel in spec.hands.items():
            if chain not in grasps or chain not in chains:
                if chain in contact:  # (let go: the tick forgets it)
                    return False
                continue
            me = vector(channel)
            if me is None:
                continue
            seen = perf.get(channel)
            if seen is None:  # (the first sample: its rates begin at 0, Python's)
                if not first:
                    return False
                tr._performer_rate(channel, me, step)
                seen = perf[channel]
            start = contact.get(chain)
            if start is None:  # (a contact begins: the figure's angle then, Python's)
                return False
            joint = grasps[chain][0]
            pins.append(joint)
            hands.append(channel)
            anchor = self._anchors.get(joint) or self._anchor(joint)
            row += (*anchor, *start, *me, seen[3], seen[4])  # (the rates: the kernel's
            seen_at += (seen[0], seen[1])  # at its first tick after a sample since the
            seen_step.append(seen[2])  # last they were worked out at: pk_contact_rates)
            xy += (get(channel + ".x"), get(channel + ".y"))
        if len(contact) > len(pins):  # (a contact whose hand let go, or no vector)
            for chain in contact:
                if chain not in grasps or chain not in chains:
                    return False
        n = len(pins)
        if pins != self._pins:  # the grasps' pins (a grasp, a re-seat: new joints)
            if n > 4:
                return False
            self._pins = pins
            for k, joint in enumerate(pins):
                self._c_body[k] = self.poll.pointer(joint.b._body)
        self._c_row[0:len(row)] = row
        p.c_sv[0:len(seen_at)], p.c_seen[0:n], p.c_xy[0:len(xy)] = seen_at, seen_step, xy
        hands = tuple(hands)
        if hands != self._hands:  # (a sample's values: the angles', then each hand's)
            self._hands = hands
            self.key = tuple(self.names) + tuple(
                f"{h}.{a}" for h in hands for a in ("x", "y"))
        c = tr.character
        if self._com_of is not c.bodies:  # (the plan's centre of mass: poll_fill.fill's,
            args = self._com_args = c._com_bound(self.poll.kernel)[2]  # these bodies')
            p.com_bodies, p.com_mass, p.com_gx, p.com_gy, p.com_n, p.com_total = args[:6]
            p.c_swing, p.c_swing_d = spec.swing, spec.swing_damping
            p.c_spring, p.c_damp = spec.spring, spec.damping
            p.c_mass, p.c_period, p.c_dt = c.mass, tr.period, tr.dt
            p.c_body, p.c_row = self._c_body, self._c_row
            self._com_of = c.bodies
        # a machine reads what the contacts move (VELOCITY): they come first (c_late);
        # an until reading it too, which Python polls before them: Python's
        late = 1 if n and self.poll._velocity & 1 else 0
        if late and (self.poll._velocity & 2 or p.com_n > 64):  # (PK_LATE)
            return False
        p.c_n, p.c_late = n, late
        return True

    def _anchor(self, joint) -> tuple:
        """A pin's point on the body it holds (``Simulation.grasp_point``'s)."""
        if len(self._anchors) > 16:  # (the pins of grasps gone)
            self._anchors.clear()
        got = self._anchors[joint] = tuple(joint.anchor_b)
        return got


def may_track(tr) -> bool:
    """Whether the tracker's tick may be the kernel's, by its own state (asked first
    in ``PollPlan.ready``, at every tick of a tracking interface: kept cheap)."""
    if tr.mode != ANGLES or tr.lost or tr.due or tr.blend_at is not None \
            or tr.impact_at is not None or tr.getup is not None or tr.hold is not None \
            or tr.back is not None or tr.lib is not None or tr.search_at is not None \
            or tr.scaled:
        return False
    if tr.spec.contacts is None and not ANGLES_ALONE:
        return False
    # (a walk in place turns the performer's channels into a walk: Python's)
    return tr.walk_cycle is None or tr.spec.walk_in_place is None


def track_part(plan, step: int, resume: bool) -> int | None:
    """``PollPlan.ready``'s tracker: the step its run must stop at (``NEVER``-like
    large without a tracker), the plan's track filled or cleared; None: Python's."""
    rt = plan.runtime
    tr = rt.tracker
    if not tr.busy:
        track = plan._angles
        if track is not None and track._on:
            plan.plan.track, track._on = plan.ffi.NULL, False
        return NEVER
    track = plan._angles
    if track is None:
        track = plan._angles = AngleTrack(plan)
    until = track.fill(step, resume)
    if until is None and track._on:
        plan.plan.track, track._on = plan.ffi.NULL, False
    return until

