"""The sampled run that expectations read: ``Trajectory`` (numpy arrays, one row per
sample) and ``Sampler``, the ``on_tick`` callback that records it during a replay.

A module of its own because three kinds of code read it - the replay engine
(``puppet.timeline.replay``), the expectations (``puppet.timeline.expectations``) and
the tools' searches - and none of them should need the others to get at it. numpy is
imported only when a trajectory is built (a plain replay does not sample).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from puppet.physics.snapshot import touching as snapshot_touching
from puppet.physics.snapshot import touching_shapes as snapshot_touching_shapes

if TYPE_CHECKING:
    import numpy as np

    from puppet.session import Session

SAMPLE_RATE = 120.0  # Hz: trajectory samples a second, on any simulation step


def sample_every(dt: float) -> int:
    """Steps between trajectory samples on a ``dt`` s step: ``SAMPLE_RATE`` a second
    (4 at 1/480 s, 2 at 1/240 s). A fixed count of steps would read a 1/240 s run at
    60 Hz, in step with a 60 Hz performer's frames: always at one point of each (a
    mocap feat's tracking error then hung on when its frames came, not on the figure)."""
    return max(1, round(1.0 / (SAMPLE_RATE * dt)))


_NAN = float("nan")


@dataclass
class Trajectory:
    """Sampled states of a replay, one row per sample (numpy arrays).

    Per link (columns in ``links`` order): ``x``, ``y`` (centre of mass, m), ``angle``
    (rad), ``lowest`` (lowest point of the link's shapes, m), ``contact`` (touching
    something outside the character; at the first sample, step 0, the next sample's:
    before the first step there are no contacts yet). Per joint (``joints`` order): ``joint_angle``,
    ``joint_target`` (rad), ``joint_channel`` (the value of the input channel named
    like the joint - a performance's angle for it - in rad, NaN where none came yet).
    ``com`` is (n, 2). ``root_angle`` is the root link's angle (rad, as ``angle``'s
    column for the root: unwrapped, 0 in the model's orientation). Read a link's column
    with ``index``: ``traj.y[:, traj.index("base")]``; a joint's with
    ``traj.joints.index``: ``traj.joint_angle[:, traj.joints.index("hip_near")]``.
    ``state`` and ``mode`` (object arrays of names, None without
    states or modes) are the interface's state and mode at each
    sample, for expectations about what the character was doing; ``state_names`` and
    ``mode_names`` are the ones the interface defines (every version, if it was
    reloaded), so such an expectation can say a name does not exist. ``held`` is what
    the chains hold (grasps) at each sample. ``touches`` (only when the Sampler was
    asked for them: ``never_touched`` reads them) is what each link touched at each
    sample: a tuple of (link column, what, name, x, y) per contact point, ``what`` being
    'prop' (``name`` the prop's), 'ground' (``name`` the polyline's, '' unnamed) or
    'other'; ``ground_names`` are the scene's ground polylines' names, in order. After
    a rewind the abandoned branch's samples are dropped: the trajectory is the history
    that was kept.
    """

    links: list[str]
    joints: list[str]
    step: np.ndarray
    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    angle: np.ndarray
    lowest: np.ndarray
    contact: np.ndarray
    com: np.ndarray
    root_angle: np.ndarray
    joint_angle: np.ndarray
    joint_target: np.ndarray
    joint_channel: np.ndarray  # the channel named like each joint (rad; NaN: none yet)
    state: np.ndarray
    mode: np.ndarray
    state_names: list[str]
    mode_names: list[str]
    # what the chains hold at each sample: a tuple of (chain, prop or None for the world,
    # grasp point name or None: a segment or a world point, x, y of the held point in m)
    # per sample, () when nothing is held
    held: np.ndarray | None = None
    prop_points: dict[str, list[str]] | None = None  # prop -> its grasp points, in order
    # per sample: ((link column, 'prop' | 'ground' | 'other', name, x, y), ...) of every
    # contact point of the character with the scene (None: not recorded)
    touches: np.ndarray | None = None
    ground_names: list[str] | None = None  # the scene's ground polylines' names ('': none)

    def __post_init__(self):
        # the sample at step 0 is taken before the first step, when pymunk has found no
        # contacts yet: it would read as a flight (a standing start counted as a hop,
        # a one-sample 'airborne'); it takes the next sample's contacts instead
        if len(self.step) > 1 and self.step[0] == 0:
            self.contact[0] = self.contact[1]
            if self.touches is not None:
                self.touches[0] = self.touches[1]

    def index(self, link: str) -> int:
        """The column of a link in the per-link arrays; ValueError naming the links
        (and, for a joint's name, where joints are read) for another name."""
        try:
            return self.links.index(link)
        except ValueError:
            pass
        joint = (f"'{link}' is a joint: its columns are in joint_angle, joint_target and "
                 f"joint_channel, at trajectory.joints.index('{link}')"
                 if link in self.joints else
                 f"joints are read with trajectory.joints.index(NAME) in joint_angle, "
                 f"joint_target, joint_channel (joints: {', '.join(self.joints) or 'none'})")
        raise ValueError(f"no link '{link}' in the trajectory; the links are: "
                         f"{', '.join(self.links)}; {joint}") from None

    def __len__(self) -> int:
        return len(self.t)


class Sampler:
    """An ``on_tick`` callback that records the session's state.

    It runs at every sample of every replay (most of a test replay's time went here),
    so it reads pymunk through its C library directly, with what does not change (the
    links' centres of gravity, the servos' springs and bodies) looked up once per
    set of bodies (a restore rebuilds them): the same C calls pymunk's properties make,
    so the same numbers to the bit (tested against the plain reading)."""

    def __init__(self, session: Session, touches: bool = False):
        """``touches``: also record what each link touches and where (``Trajectory.touches``:
        slower, so only when an expectation reads it)."""
        c = session.character
        self.touches = touches
        self.ground_names = [g.name for g in session.sim.scene_spec.ground]
        self.links = list(c.link_order)
        self.joints = list(c.servos)
        self.root = c.spec.root
        self._no_channels = [_NAN] * len(self.joints)
        self.rows: list[tuple] = []
        self.state_names: dict[str, None] = {}  # ordered sets
        self.mode_names: dict[str, None] = {}
        self._runtime = None
        self.prop_points = {n: list(p.points) for n, p in session.sim.props.items()}
        self._take = (0, 0)  # the session's last take seen (Session.last_take)
        self._key = None  # the bodies the plan below was made for
        from pymunk._chipmunk_cffi import ffi, lib

        self._lib = lib
        touched = self._touched = [0]

        @ffi.callback("void(cpBody *, cpArbiter *, void *)")
        def count(body, arbiter, data):  # a link's arbiters: anything outside it
            touched[0] += 1

        self._count, self._null = count, ffi.NULL

    def _plan(self, c) -> None:
        """Per link (in ``links`` order): body, its C pointer, centre of gravity, the
        C pointers of its shapes; the com's bodies in ``Character.com``'s order."""
        self._key = c.bodies[self.links[0]]
        self._per_link = [(c.bodies[n], c.bodies[n]._body, tuple(c.bodies[n].center_of_gravity),
                           [sh._shape for sh in c.shapes[n]]) for n in self.links]
        at = {n: i for i, n in enumerate(self.links)}
        self._com_order = [(at[n], b.mass) for n, b in c.bodies.items()]
        self._mass = c.mass
        link_of = {id(c.bodies[n]): i for i, n in enumerate(self.links)}
        # a joint's angle is its child's angle less its parent's: read once per link
        self._servos = [(link_of[id(c.servos[j].child)], link_of[id(c.servos[j].parent)],
                         c.servos[j].spring) for j in self.joints]
        self._root = at[c.spec.root]

    def __call__(self, session: Session) -> None:
        step = session.steps
        rt = session.runtime
        if rt is not self._runtime:  # the start, or a reload: names it may have added
            self._runtime = rt
            self.state_names.update(dict.fromkeys(rt.spec.states))
            self.mode_names.update(dict.fromkeys(rt.spec.modes))
        if self.rows and step <= self.rows[-1][0]:  # time went back: a rewind
            while self.rows and self.rows[-1][0] >= step:
                self.rows.pop()
        take = getattr(session, "last_take", None)
        if take is not None and take != self._take:  # a branch taken up: the samples
            self._take = take  # after its fork belonged to the future left
            while take[0] and self.rows and self.rows[-1][0] > take[1]:
                self.rows.pop()
        c = session.character
        if self._key is not c.bodies[self.links[0]]:  # a restore rebuilds all the bodies
            self._plan(c)
            if self.touches:
                self._things = _things(session.sim)
        lib, touched, count, null = self._lib, self._touched, self._count, self._null
        # each shape's box worked out from its body now (as pymunk's cache_bb), not the one
        # cached at the last step or add: after a re-seat or restore, adding a body's
        # later shapes re-sets its position (Chipmunk sums their mass), so its first
        # shape's cached box can be an ulp off until the next step (issue 29). The write
        # is harmless: a step works every dynamic shape's box out again before using it.
        to_world, get_bb, each = lib.cpBodyLocalToWorld, lib.cpShapeCacheBB, lib.cpBodyEachArbiter
        per_link = []
        space = self._per_link[0][0].space
        restored = getattr(space, "_puppet_contacts", None)  # just restored: the snapshot's
        if restored is not None and lib.cpSpaceGetTimestamp(space._space) != restored[0]:
            restored = None  # contacts (see snapshot.restored_contacts); else the arbiters
        if restored is not None:
            restored = snapshot_touching(restored)
        for body, ptr, cog, shapes in self._per_link:
            p = to_world(ptr, cog)
            if restored is not None:
                touching = bool(restored.get(body))
            else:
                touched[0] = 0
                each(ptr, count, null)
                touching = touched[0] > 0
            per_link.append((p.x, p.y, body.angle, min(get_bb(sh).b for sh in shapes),
                             touching))
        mx = my = 0.0  # Character.com, from the positions just read, in its order
        for i, mass in self._com_order:
            mx += mass * per_link[i][0]
            my += mass * per_link[i][1]
        self.rows.append((step, session.time, per_link, (mx / self._mass, my / self._mass),
                          per_link[self._root][2],
                          [per_link[i][2] - per_link[k][2] for i, k, _ in self._servos],
                          [spring.rest_angle for _, _, spring in self._servos],
                          [rt.channels.get(j, _NAN) for j in self.joints] if rt.channels
                          else self._no_channels, rt.state, rt.mode,
                          _held(session.sim) if session.sim.grasps else (),
                          self._touches(restored) if self.touches else None))

    def _touches(self, restored) -> tuple:
        """(link column, what, name, x, y) of every contact point of the links now: from
        the arbiters, or (just restored) from the snapshot's contacts."""
        out = []
        things = self._things
        if restored is not None:
            shapes = snapshot_touching_shapes(self._per_link[0][0].space._puppet_contacts)
            for k, (body, *_) in enumerate(self._per_link):
                for other, (x, y) in shapes.get(body, ()):
                    out.append((k, *things.get(other, ("other", "")), x, y))
            return tuple(out)
        for k, (body, *_) in enumerate(self._per_link):
            def collect(arbiter, k=k, body=body):
                a, b = arbiter.shapes
                other, first = (b, True) if a.body is body else (a, False)
                what = things.get(other, ("other", ""))
                for p in arbiter.contact_point_set.points:
                    q = p.point_a if first else p.point_b
                    out.append((k, *what, q.x, q.y))
            body.each_arbiter(collect)
        return tuple(out)

    def trajectory(self) -> Trajectory:
        import numpy as np

        rows = self.rows
        n, nl, nj = len(rows), len(self.links), len(self.joints)
        link = np.array([r[2] for r in rows], dtype=float).reshape(n, nl, 5)
        return Trajectory(
            links=self.links, joints=self.joints,
            step=np.array([r[0] for r in rows], dtype=np.int64),
            t=np.array([r[1] for r in rows], dtype=float),
            x=link[:, :, 0], y=link[:, :, 1], angle=link[:, :, 2], lowest=link[:, :, 3],
            contact=link[:, :, 4].astype(bool),
            com=np.array([r[3] for r in rows], dtype=float).reshape(n, 2),
            root_angle=np.array([r[4] for r in rows], dtype=float),
            joint_angle=np.array([r[5] for r in rows], dtype=float).reshape(n, nj),
            joint_target=np.array([r[6] for r in rows], dtype=float).reshape(n, nj),
            joint_channel=np.radians(np.array([r[7] for r in rows],
                                              dtype=float).reshape(n, nj)),
            state=np.array([r[8] for r in rows], dtype=object),
            mode=np.array([r[9] for r in rows], dtype=object),
            state_names=list(self.state_names), mode_names=list(self.mode_names),
            held=_object_array([r[10] for r in rows]), prop_points=self.prop_points,
            touches=(_object_array([r[11] for r in rows]) if self.touches and all(
                len(r) > 11 for r in rows) else None),
            ground_names=list(self.ground_names))


def _things(sim) -> dict:
    """shape -> (what, name) of every shape of the scene: a prop's ('prop', its name),
    a ground segment's ('ground', its polyline's name)."""
    out = {}
    for name, prop in sim.props.items():
        for shape in prop.shapes:
            out[shape] = ("prop", name)
    segments = iter(sim.ground)
    for ground in sim.scene_spec.ground:  # build_ground: each polyline's segments in turn
        for _ in range(len(ground.points) - 1):
            out[next(segments)] = ("ground", ground.name)
    return out


def _object_array(items: list) -> np.ndarray:
    import numpy as np

    out = np.empty(len(items), dtype=object)
    out[:] = items
    return out


def _held(sim) -> tuple:
    """(chain, prop, grasp point name, x, y) of every grasp held now, sorted by chain;
    the name is the prop's grasp point at the held place (None: a segment, a world
    point), x and y where the held point is (m)."""
    out = []
    for name, (_, prop) in sorted(sim.grasps.items()):
        point = None
        x, y = sim.grasp_point(name)
        if prop is not None:
            distance, _, nearest = sim.props[prop].nearest((x, y))
            point = nearest if distance < 1e-6 else None
        out.append((name, prop, point, x, y))
    return tuple(out)


