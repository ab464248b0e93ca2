"""KD tracking's pulls in the compiled kernel (``physics.kernel``): what the tracker
hands it once (the joint chain, the links' plan, the feet's lowest points) and at each
control step (the channels' values), and the tracker's per-link memory of the last
sample (``prev``, ``vel``, ``spin``) kept in the kernel's arrays.

The kernel does what ``Tracker._pull`` and ``_write_targets`` do in Python, in the same
operations (``kernel_source``): the same bits. What stays in Python is what happens
rarely or calls back into the rest of puppet: the ground's height under the figure,
judging a push, the protective step's target, getting up's contact test, a blend into
tracking.
"""

from __future__ import annotations


class Kept:
    """A tracker attribute (``prev``, ``vel``, ``spin``) that lives in the kernel's
    arrays when the tracker has one (``_kern``), in the instance otherwise: reading
    it gives the dict the Python path keeps, and assigning one writes it back."""

    def __init__(self, name: str):
        self.name, self.slot = name, "_kept_" + name

    def __get__(self, obj, cls=None):
        if obj is None:
            return self
        kern = obj.__dict__.get("_kern")
        if kern is None:
            return obj.__dict__.get(self.slot)
        return getattr(kern, "get_" + self.name)()

    def __set__(self, obj, value) -> None:
        kern = obj.__dict__.get("_kern")
        if kern is None:
            obj.__dict__[self.slot] = value
        else:
            getattr(kern, "set_" + self.name)(value)


def _ints(ffi, values):
    return ffi.new("int[]", list(values) or [0])


def _doubles(ffi, values):
    return ffi.new("double[]", list(values) or [0.0])


def _chain(ffi, rows, index: dict, names: dict, keep: list):
    """A ``pk_chain`` of ``tracked_chain``'s rows; each channel's place in the values
    is added to ``names`` (channel -> index), the arrays to ``keep``."""
    values = [-1 if r[5] is None else names.setdefault(r[5], len(names)) for r in rows]
    c = ffi.new("pk_chain *")
    c.n = len(rows)
    for field, vs in (("parent", [index[r[1]] for r in rows]),
                      ("child", [index[r[2]] for r in rows]), ("value", values),
                      ("limited", [r[6] is not None for r in rows])):
        keep.append(_ints(ffi, vs))
        setattr(c, field, keep[-1])
    for field, vs in (("ax", [r[3] for r in rows]), ("ay", [r[4] for r in rows]),
                      ("lo", [0.0 if r[6] is None else r[6][0] for r in rows]),
                      ("hi", [0.0 if r[6] is None else r[6][1] for r in rows])):
        keep.append(_doubles(ffi, vs))
        setattr(c, field, keep[-1])
    keep.append(c)
    return c


class TrackKernel:
    """A tracker's ``pk_track``: built once, its bodies and gains bound again when a
    restore re-binds them (``bind``)."""

    def __init__(self, kernel, tracker, points_of):
        self.kernel, ffi = kernel, kernel.ffi
        self.lib = kernel.lib
        spec, cs = tracker.spec, tracker.character.spec
        links = [link.name for link in cs.links]
        index = {n: i for i, n in enumerate(links)}
        root = spec.root
        names: dict[str, int] = {root.x: 0, root.y: 1, root.angle: 2}
        keep: list = []  # the arrays the struct points at
        t = self.t = ffi.new("pk_track *")

        def arr(kind, values, field):
            a = _ints(ffi, values) if kind == "int" else _doubles(ffi, values)
            keep.append(a)
            setattr(t, field, a)
            return a

        # the performed pose's chain (kd_pull.tracked_chain), its values' places
        chain = self.chain = _chain(ffi, tracker._tracked_rows(), index, names, keep)
        t.chain = chain
        t.root = index[cs.root]
        t.hinge_x, t.hinge_y = cs.joint(root.at).anchor
        # the joint targets (Tracker._write_targets), in the tracker's joints' order
        self.target_joints = list(tracker.joints)
        lims = [tracker.limits.get(j) for j in self.target_joints]
        t.n_targets = len(self.target_joints)
        arr("int", [names.setdefault(tracker.joints[j], len(names))
                    for j in self.target_joints], "target_value")
        arr("int", [lim is not None for lim in lims], "target_limited")
        arr("double", [0.0 if lim is None else lim[0] for lim in lims], "target_lo")
        arr("double", [0.0 if lim is None else lim[1] for lim in lims], "target_hi")
        self.springs = ffi.new("void *[]", max(1, len(self.target_joints)))
        t.spring = self.springs
        # the rows: every link (Tracker.pulled), in order
        self.rows = list(tracker.pulled)
        self.row_of = {n: r for r, n in enumerate(self.rows)}
        n = t.rows = len(self.rows)
        arr("int", [index[name] for name in self.rows], "link")
        self.soles = list(tracker.soles)
        arr("int", [name in tracker.soles for name in self.rows], "sole")
        self.bodies = ffi.new("void *[]", max(1, n))
        t.body = self.bodies
        for field in ("m", "gx", "gy", "ks", "ds", "m_T"):
            arr("double", [0.0] * n, field)
        # the lowest points: [0] the feet's, [1] every link's (a get-up's)
        for k, table in enumerate((tracker.soles, points_of())):
            pts = [(index[link], px, py, r) for link, points in table.items()
                   for px, py, r in points]
            t.n_points[k] = len(pts)
            for field, vs in (("point_link", [p[0] for p in pts]),):
                a = _ints(ffi, vs)
                keep.append(a)
                getattr(t, field)[k] = a
            for j, field in ((1, "px"), (2, "py"), (3, "pr")):
                a = _doubles(ffi, [p[j] for p in pts])
                keep.append(a)
                getattr(t, field)[k] = a
        arr("double", [0.0] * (5 * len(links)), "poses")
        arr("double", [0.0] * (3 * n), "targets")
        arr("double", [0.0] * (3 * n), "prev")
        arr("int", [0] * n, "prev_has")
        arr("double", [0.0] * (2 * n), "vel")
        arr("int", [0] * n, "vel_has")
        arr("double", [0.0] * n, "spin")
        arr("int", [0] * n, "spin_has")
        self._keep = keep
        self.names = list(names)  # the channels read, root x, y, angle first
        self.row_joints = [tracker.joint_of.get(name) for name in self.rows]
        self._bound = None
        self.bodies_of = None  # the character's bodies (dict) bound last

    # -- binding ---------------------------------------------------------------------
    def bind(self, plan, servos) -> None:
        """``plan`` (``kd_pull.link_plan``'s rows, in row order) and the servos, when
        they are not those bound last (a restore makes new ones)."""
        if self._bound is not None and self._bound[0] is plan and self._bound[1] is servos:
            return
        t, pointer = self.t, self.kernel.pointer
        for r, (_, cb, _, m, gx, gy, _, ks, ds, m_T, _) in enumerate(plan):
            self.bodies[r] = pointer(cb)
            t.m[r], t.gx[r], t.gy[r], t.ks[r], t.ds[r], t.m_T[r] = m, gx, gy, ks, ds, m_T
        for j, joint in enumerate(self.target_joints):
            self.springs[j] = pointer(servos[joint].spring._constraint)
        self._bound = (plan, servos)

    # -- the per-sample memory (Kept) --------------------------------------------------
    def get_prev(self):
        t = self.t
        if not t.has_prev:
            return None
        out = {}
        for r, name in enumerate(self.rows):
            k = t.prev_has[r]
            if k:
                out[name] = tuple(t.prev[3 * r + i] for i in range(k))
        return out

    def set_prev(self, prev) -> None:
        t = self.t
        t.has_prev = prev is not None
        for r, name in enumerate(self.rows):
            p = None if prev is None else prev.get(name)
            t.prev_has[r] = 0 if p is None else len(p)
            for i, v in enumerate(p or ()):
                t.prev[3 * r + i] = v

    def get_vel(self) -> dict:
        t = self.t
        return {name: (t.vel[2 * r], t.vel[2 * r + 1]) for r, name in enumerate(self.rows)
                if t.vel_has[r]}

    def set_vel(self, vel) -> None:
        t = self.t
        for r, name in enumerate(self.rows):
            v = vel.get(name)
            t.vel_has[r] = v is not None
            if v is not None:
                t.vel[2 * r], t.vel[2 * r + 1] = v
        # (a name outside the rows is never read: the Python path reads rows only)

    def get_spin(self) -> dict:
        t, row = self.t, self.row_of
        return {name: t.spin[row[name]] for name in self.soles
                if name in row and t.spin_has[row[name]]}

    def set_spin(self, spin) -> None:
        t = self.t
        for r, name in enumerate(self.rows):
            s = spin.get(name)
            t.spin_has[r] = s is not None
            if s is not None:
                t.spin[r] = s

    def targets(self) -> dict:
        """This step's targets as ``_pull``'s dict: (x, y) a link, (x, y, angle) a foot."""
        t = self.t
        return {name: tuple(t.targets[3 * r + i] for i in range(3 if t.sole[r] else 2))
                for r, name in enumerate(self.rows)}


class ChainPose:
    """``kd_pull.channel_pose`` of one chain (``tracked_chain``'s rows) by the kernel:
    ``pose(ch, ...)`` fills ``poses`` (x, y, angle, cos, sin per link index)."""

    def __init__(self, kernel, rows, links: list[str], root: str):
        ffi = kernel.ffi
        self.lib, self.ffi = kernel.lib, ffi
        self.index = {n: i for i, n in enumerate(links)}
        names: dict[str, int] = {}
        self._keep: list = []
        self.chain = _chain(ffi, rows, self.index, names, self._keep)
        self.names = list(names)
        self.root = self.index[root]
        self.poses = ffi.new("double[]", 5 * len(links))

    def pose(self, ch: dict, ox: float, oy: float, angle: float, cos: float, sin: float):
        vals = list(map(ch.get, self.names))
        has = self.ffi.NULL
        if None in vals:
            has = bytes(v is not None for v in vals)
            vals = [0.0 if v is None else v for v in vals]
        self.lib.pk_pose(self.chain, vals or [0.0], has, self.root, ox, oy, angle, cos, sin,
                         self.poses)
        return self.poses
