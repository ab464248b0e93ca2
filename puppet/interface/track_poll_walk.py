"""``TrackPoll``'s walk in place (``interface.track_poll``; the C: ``pk_walk`` in
``physics.kernel_poll_track``): the gait cycle's table, the rows of a sample's step
(``pk_walk_step``: ``WalkInPlace._feet_gap``'s chain, the feet, the lifts), and the
walk's state into the table before a run and back into the tracker after it. Kept
apart so that ``track_poll`` stays readable; ``self`` is the ``TrackPoll``.
"""

from __future__ import annotations

from puppet.interface.controllers.kd_kernel import _chain
from puppet.interface.controllers.tracking import PRESS


def walk_table(self, tr, n: int):
    """``pk_walk`` of the tracker's gait cycle (its frames, drift and the rows of
    ``GaitCycle.blend_into`` the tracker reads), for ``n`` values."""
    ffi, cycle, spec = self.ffi, tr.walk_cycle, tr.spec.walk_in_place
    w = ffi.new("pk_walk *")
    keep = self._walk_keep = []

    def arr(kind, values):
        keep.append(ffi.new(kind + "[]", list(values) or [0]))
        return keep[-1]
    w.frames = arr("double", [v for frame in cycle.frames for v in frame])
    w.n_frames, w.width, w.xi = len(cycle.frames), len(cycle.names), cycle.x
    w.a, w.b, w.stride = cycle.a, cycle.b, cycle.stride
    w.start = cycle._raw_one(cycle.a, cycle.x)  # (GaitCycle.travel's start)
    w.drift = arr("double", cycle.drift)
    index = {name: i for i, name in enumerate(cycle.names)}
    place = {name: i for i, name in enumerate(self.tk.names)}
    rows = [(place[name], index[name]) for name in dict.fromkeys(spec.joints)
            if name in index and name in place]
    w.n_rows = len(rows)
    w.row_val, w.row_ch = arr("int", [r[0] for r in rows]), arr("int", [r[1] for r in rows])
    w.dt, w.stop_after, w.blend = tr.dt, spec.stop_after, spec.blend
    w.n_vals = n
    self._raw, self._raw_has = arr("double", [0.0] * n), ffi.new("char[]", n)
    view_has = ffi.new("char[]", n)
    keep += [self._raw_has, view_has]  # (the struct's pointers own nothing)
    w.raw, w.raw_has = self._raw, self._raw_has
    w.view, w.view_has = arr("double", [0.0] * n), view_has
    w.lift = bool(tr.soles) and tr.ground_at is not None
    feet_rows(self, tr, w, keep)
    return w


def feet_rows(self, tr, w, keep: list) -> None:
    """``pk_walk_step``'s rows: ``WalkInPlace._feet_gap``'s chain (its values the
    raw's places), the feet, the lift, steps and the cycle's lifts (``feet`` NULL:
    no gap, as ``_feet_gap`` finds none; ``_walk_samples`` False: a channel of the
    chain the raw lacks, the samples' steps Python's)."""
    ffi, spec, root = self.ffi, tr.spec.walk_in_place, tr.spec.root
    w.feet, w.f_lift, (w.f_lo, w.f_hi) = ffi.NULL, spec.lift, spec.steps
    self._walk_samples = True
    if root is None or len(tr.soles) < 2 or root.angle not in self.tk.names:
        return
    rows, feet = tr._feet_chain()
    links = [link.name for link in tr.character.spec.links]
    index = {name: i for i, name in enumerate(links)}
    names = {name: i for i, name in enumerate(self.tk.names)}
    w.feet = _chain(ffi, rows, index, names, keep)
    if len(names) > len(self.tk.names):  # (a channel the raw lacks)
        self._walk_samples = False
    w.f_root, w.f_angle = index[tr.character.spec.root], names[root.angle]
    for k, (foot, gx, gy) in enumerate(feet):
        w.f_link[k], w.f_gx[k], w.f_gy[k] = index[foot], gx, gy
    w.f_lifts = list(tr._cycle_lifts())
    keep.append(ffi.new("double[]", 5 * len(links)))
    w.poses = keep[-1]


def walk_from(self, tr, w, ch) -> bool:
    """The walk's state and the performer's values (``pk_walk``) as they are now;
    False when the kernel cannot walk them (the scene's ground is another's)."""
    if not self._ground_ok(tr):
        return False
    w.raw_has = self._into(ch, self._raw, self._raw_has)
    last_side, last_at, period, walking, phase, speed, travel, weight, at = tr.walk
    w.walking, w.phase, w.speed, w.travel, w.weight = walking, phase, speed, travel, weight
    w.last_side = -1 if last_side is None else last_side
    w.has_period, w.period = period is not None, period or 0.0
    w.has_last_at, w.last_at = last_at is not None, last_at or 0
    w.has_at, w.at = at is not None, at or 0
    clearance = ch.get(tr.spec.root.clearance, 0.0)
    w.extra = clearance if clearance > 0.0 else -PRESS
    self.plan.walk = w
    return True


def walked_back(self, tr) -> None:
    """The walk's state after the kernel's ticks, into the tracker."""
    w = self._walk  # (a sample's step may have moved the side, period and speed)
    tr.walk = [None if w.last_side < 0 else w.last_side,
               w.last_at if w.has_last_at else None, w.period if w.has_period else None,
               bool(w.walking), w.phase, w.speed, w.travel, w.weight, w.at]
    tr._walk_out = None  # (the view at a step: the same worked out again)
