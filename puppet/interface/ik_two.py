"""The two-joint chain's IK (an arm, Luxo's lamp, the ladder's legs), unrolled.

A reach re-solves its chain at every physics step, so this is the hottest Python of
the reaching feats (the ladder climb, the monkey bars). ``TwoLink.solve`` is
``ik._two_link`` followed, when a joint limit is in the way, by ``ik.solve_dls`` from
the clamped answer - operation for operation the same floating-point arithmetic in the
same order (so every recorded log replays to the same bits), without the lists,
generators and calls of the general solvers (tests/test_ik.py compares the two bit for
bit). How the general code's sums and clamps map here:

- ``sum(x * x for ...)`` adds from an int 0, and ``0 + v`` is ``v`` for a square; a sum
  whose terms may be -0.0 keeps its leading ``0.0 +`` (it makes -0.0 into 0.0);
- ``max(lo, v)`` is ``v if v > lo else lo`` and ``min(hi, m)`` is ``m if m < hi else hi``
  (the builtins keep the first of equals, NaN included);
- ``x - 0.0`` is ``x``, and a clamped value clamped again is the same value.
"""

from __future__ import annotations

import math

from puppet.physics import kernel as _kernel

_atan2, _acos, _hypot = math.atan2, math.acos, math.hypot
# math's cos, sin and remainder as C answers a blown-up state (the kernel's pk_two_link):
# NaN, where Python raises ValueError (the session's blow-up check recovers it)
_cos, _sin, _rem = _kernel.cos, _kernel.sin, _kernel.remainder

_TWO_PI = 2.0 * math.pi  # (ik._wrap's period)


def round_clamp(q: float, clamped: float, lo: float, hi: float) -> float:
    """An angle ``q`` (within one turn, -pi..pi) past a joint's limits, clamped to the
    limit nearer round the circle: ``clamped`` (the nearer one on the line) unless the
    other is nearer the other way round. An arm at its 180 deg limit whose answer
    wraps to -179.9 deg stays at 180, where the clamp on the line threw it to its
    -60 deg limit (a monkey-bars arm straight up, holding its bar, swung down and
    round at the end of a reach). NaN (a blown-up state) stays as clamped."""
    if q < lo and q + _TWO_PI - hi < lo - q:
        return hi
    if q > hi and lo + _TWO_PI - q < q - hi:
        return lo
    return clamped


class TwoLink:
    """A two-joint chain's solver: the closed form nearest the preferred bend, then
    damped least squares within the limits when the closed form is clamped."""

    __slots__ = ("l1", "l2", "p1", "p2", "l1sq", "l2sq", "den", "links", "limits",
                 "lam2", "tol2", "iterations", "_c")

    def __init__(self, closed, links, limits, damping: float, tolerance: float,
                 iterations: int):
        l1, l2, self.p1, self.p2 = closed
        self.l1, self.l2 = l1, l2
        self.l1sq, self.l2sq, self.den = l1 * l1, l2 * l2, 2.0 * l1 * l2
        (ax0, ay0), (ax1, ay1) = links
        self.links = (ax0, ay0, ax1, ay1)
        self.limits = tuple(limits)
        self.lam2 = damping * damping
        self.tol2 = tolerance * tolerance
        self.iterations = iterations
        self._c = None  # (kernel, pk_two_link, its parameters, out): compiled, per kernel

    def _compiled(self, k) -> tuple:
        """``pk_two_link`` (the compiled kernel's ``solve`` and ``dls``) and this chain's
        numbers as it reads them."""
        lims = [(1.0, *lim) if lim is not None else (0.0, 0.0, 0.0) for lim in self.limits]
        params = [self.l1, self.l2, self.p1, self.p2, self.l1sq, self.l2sq, self.den,
                  *self.links, *lims[0], *lims[1], self.lam2, self.tol2,
                  float(self.iterations)]
        self._c = (k, k.lib.pk_two_link, k.ffi.new("double[]", params), k.ffi.new("double[2]"))
        return self._c

    def solve(self, d0: float, d1: float, prefer_q2: float) -> tuple[float, float]:
        """Joint angles reaching for (d0, d1) (the first joint's parent frame, from the
        first joint), within the limits; as ``ik._two_link`` then ``ik.solve_dls``."""
        k = _kernel.get()
        if k is not None:  # the compiled kernel: the arithmetic below, in C
            got = self._c
            if got is None or got[0] is not k:
                got = self._compiled(k)
            _, two, params, out = got
            two(params, d0, d1, _hypot(d0, d1), prefer_q2, out)
            return out[0], out[1]
        l1, l2, p1 = self.l1, self.l2, self.p1
        dist = _hypot(d0, d1)
        c = (dist * dist - self.l1sq - self.l2sq) / self.den
        c = c if c > -1.0 else -1.0  # min(1.0, max(-1.0, c))
        c = c if c < 1.0 else 1.0
        beta = _acos(c)  # the bend nearer prefer_q2 (the first of equals); only its q1
        q2 = _rem(beta + p1 - self.p2, _TWO_PI)
        other = -_acos(c)
        q2b = _rem(other + p1 - self.p2, _TWO_PI)
        if abs(_rem(q2b - prefer_q2, _TWO_PI)) < abs(_rem(q2 - prefer_q2, _TWO_PI)):
            beta, q2 = other, q2b
        q1 = _rem(_atan2(d1, d0) - (p1 + _atan2(l2 * _sin(beta), l1 + l2 * _cos(beta))),
                  _TWO_PI)
        lim0, lim1 = self.limits
        same = True
        c1, c2 = q1, q2
        if lim0 is not None:
            m = q1 if q1 > lim0[0] else lim0[0]
            c1 = m if m < lim0[1] else lim0[1]
            same = c1 == q1
            if not same:
                c1 = round_clamp(q1, c1, lim0[0], lim0[1])
        if lim1 is not None:
            m = q2 if q2 > lim1[0] else lim1[0]
            c2 = m if m < lim1[1] else lim1[1]
            same = same and c2 == q2
            if c2 != q2:
                c2 = round_clamp(q2, c2, lim1[0], lim1[1])
        if same:
            return q1, q2
        return self.dls(d0, d1, c1, c2)  # a limit is in the way: nearest within them

    def dls(self, d0: float, d1: float, q0: float, q1: float) -> tuple[float, float]:
        """``ik.solve_dls`` for two links from a start within the limits."""
        ax0, ay0, ax1, ay1 = self.links
        lim0, lim1 = self.limits
        lo0, hi0 = lim0 if lim0 is not None else (None, None)
        lo1, hi1 = lim1 if lim1 is not None else (None, None)
        lam2, tol2 = self.lam2, self.tol2
        angle = 0.0 + q0  # forward(links, q)
        c, s = _cos(angle), _sin(angle)
        jx = 0.0 + (c * ax0 - s * ay0)
        jy = 0.0 + (s * ax0 + c * ay0)
        angle = angle + q1
        c, s = _cos(angle), _sin(angle)
        ex = jx + (c * ax1 - s * ay1)
        ey = jy + (s * ax1 + c * ay1)
        rx, ry = d0 - ex, d1 - ey
        err2 = rx * rx + ry * ry
        for _ in range(self.iterations):
            if err2 < tol2:
                break
            c0x, c0y, c1x, c1y = -ey, ex, -(ey - jy), ex - jx  # the Jacobian's columns
            if lim0 is not None:  # at a limit and the error pushes past it: left out
                push = c0x * rx + c0y * ry
                if (q0 <= lo0 and push < 0) or (q0 >= hi0 and push > 0):
                    c0x = c0y = 0.0
            if lim1 is not None:
                push = c1x * rx + c1y * ry
                if (q1 <= lo1 and push < 0) or (q1 >= hi1 and push > 0):
                    c1x = c1y = 0.0
            a = lam2 + (c0x * c0x + c1x * c1x)
            b = 0.0 + c0x * c0y + c1x * c1y
            c = lam2 + (c0y * c0y + c1y * c1y)
            det = a * c - b * b
            w0, w1 = (c * rx - b * ry) / det, (a * ry - b * rx) / det
            s0, s1 = c0x * w0 + c0y * w1, c1x * w0 + c1y * w1
            scale = 1.0
            while True:
                n0 = q0 + scale * s0
                if lim0 is not None:
                    m = n0 if n0 > lo0 else lo0
                    n0 = m if m < hi0 else hi0
                n1 = q1 + scale * s1
                if lim1 is not None:
                    m = n1 if n1 > lo1 else lo1
                    n1 = m if m < hi1 else hi1
                angle = 0.0 + n0
                c, s = _cos(angle), _sin(angle)
                njx = 0.0 + (c * ax0 - s * ay0)
                njy = 0.0 + (s * ax0 + c * ay0)
                angle = angle + n1
                c, s = _cos(angle), _sin(angle)
                nx = njx + (c * ax1 - s * ay1)
                ny = njy + (s * ax1 + c * ay1)
                nrx, nry = d0 - nx, d1 - ny
                new_err2 = nrx * nrx + nry * nry
                if new_err2 < err2 or scale < 1e-3:
                    break
                scale *= 0.5
            if new_err2 >= err2:  # no step brings it nearer: as near as it gets
                break
            moved = abs(n0 - q0) + abs(n1 - q1)
            q0, q1, jx, jy = n0, n1, njx, njy
            ex, ey, rx, ry, err2 = nx, ny, nrx, nry, new_err2
            if moved < 1e-9:  # stuck against limits: as near as it gets
                break
        return q0, q1
