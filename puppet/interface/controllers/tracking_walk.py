"""Walking in place (Oshita 2006), the tracker's part that turns a performer's stepping
on the spot into a walk forward (``tracking.walk_in_place``). A mixin of ``Tracker``:
``_performer(step)`` is what the tracker follows as the performer's channels.

The rhythm: the performed pose (the performer's channels through the figure's own
links, ``kd_pull.performed_pose``) lifts one of ``tracking.feet`` above the other; a
foot ``lift`` m higher than the other, the other foot's last, is a step (Oshita's
four phases - near up, near down, far up, far down - read as the two lifts). The time
between two steps, if it is a step's (``steps``), is the rhythm's period; with one
the figure walks. The walk is an example gait cycle of a clip of a motion library (as
Oshita blends example walks), played at the performer's rate - half a cycle a step -
and phase-locked: at each step the cycle's speed is set so that it reaches the
other foot's lift in one period, from where it is; the cycle's drift (its last frame
less its first) is spread over it so that it loops without a jump. The walk's
channels (``joints``: the legs and the pelvis) replace the performer's, blended in
and out over ``blend`` s; ``root.x`` goes on by the cycle's own travel, which stays
when the walk stops (no step for ``stop_after`` s): the figure stands where it got to.
Everything reads the channels, the control steps and the library's numbers only: a
replay walks the same.
"""

from __future__ import annotations

import math

from puppet.data.errors import DataError
from puppet.interface.controllers.kd_kernel import ChainPose
from puppet.interface.controllers.kd_pull import channel_pose, tracked_chain


class GaitCycle:
    """One gait cycle of a library clip: its channels at a phase (0..1), the cycle's
    drift spread over it, and the root's travel."""

    def __init__(self, library, spec):
        names = [c[0] for c in library.clips]
        if spec.clip not in names:
            raise DataError(library.path, None, None,
                            f"tracking.walk_in_place.clip: no clip '{spec.clip}' in the "
                            f"motion library (it has {', '.join(names)})")
        frames = library.clips[names.index(spec.clip)][1]
        rate = library.rate
        a, b = spec.cycle[0] * rate, spec.cycle[1] * rate
        if not 0 <= a < b <= len(frames) - 1:
            end = (len(frames) - 1) / rate
            raise DataError(library.path, None, None,
                            f"tracking.walk_in_place.cycle: {spec.cycle[0]:g}.."
                            f"{spec.cycle[1]:g} s is not within clip '{spec.clip}' "
                            f"(0..{end:.2f} s)")
        self.frames, self.a, self.b = frames, a, b
        self.names = library.channels
        self.x = self.names.index("root.x")
        first, last = self._raw(a), self._raw(b)
        self.drift = [v1 - v0 for v0, v1 in zip(first, last)]
        self.stride = last[self.x] - first[self.x]

    def _raw(self, u: float) -> list[float]:
        k = min(int(u), len(self.frames) - 2)
        f = u - k
        p, q = self.frames[k], self.frames[k + 1]
        return [v + (w - v) * f for v, w in zip(p, q)]

    def _raw_one(self, u: float, i: int) -> float:
        """``_raw(u)[i]``, the one value worked out (the same arithmetic)."""
        k = min(int(u), len(self.frames) - 2)
        v, w = self.frames[k][i], self.frames[k + 1][i]
        return v + (w - v) * (u - k)

    def at(self, phase: float) -> dict[str, float]:
        raw = self._raw(self.a + (self.b - self.a) * phase)
        return {n: v - d * phase for n, v, d in zip(self.names, raw, self.drift)}

    def at_some(self, phase: float, names) -> dict[str, float]:
        """``at(phase)`` of the cycle's channels among ``names`` only (the same values)."""
        index = self.__dict__.get("_index")
        if index is None:
            index = self._index = {n: i for i, n in enumerate(self.names)}
        u = self.a + (self.b - self.a) * phase
        k = min(int(u), len(self.frames) - 2)
        f = u - k
        p, q, drift = self.frames[k], self.frames[k + 1], self.drift
        out = {}
        for n in names:
            i = index.get(n)
            if i is not None:
                v = p[i]
                out[n] = v + (q[i] - v) * f - drift[i] * phase
        return out

    def travel(self, phase: float) -> float:
        """m: the root's travel from the cycle's start to ``phase``."""
        x = self.x
        start = self.__dict__.get("_start")
        if start is None:  # (the same value each time: worked out once)
            start = self._start = self._raw_one(self.a, x)
        return self._raw_one(self.a + (self.b - self.a) * phase, x) - start

    def blend_into(self, out: dict, ch: dict, phase: float, names, weight: float) -> None:
        """``out[n] = u + (w - u) * weight`` for the cycle's channels among ``names``,
        ``w`` its value at ``phase`` (``at_some``) and ``u`` ``ch``'s (``w`` if none):
        ``WalkInPlace._walked``'s blend, without the dict in between."""
        rows = self.__dict__.get("_blend_rows")
        if rows is None or rows[0] is not names:
            index = {n: i for i, n in enumerate(self.names)}
            rows = self._blend_rows = (names, [(n, index[n]) for n in dict.fromkeys(names)
                                               if n in index])
        u = self.a + (self.b - self.a) * phase
        k = min(int(u), len(self.frames) - 2)
        f = u - k
        p, q, drift, get = self.frames[k], self.frames[k + 1], self.drift, ch.get
        for n, i in rows[1]:
            v = p[i]
            w = v + (q[i] - v) * f - drift[i] * phase
            c = get(n, w)
            out[n] = c + (w - c) * weight


class WalkInPlace:
    walk_cycle: GaitCycle | None = None  # the runtime sets it (from the library)

    def _walk_reset(self) -> None:
        # [last foot lifted (0/1/None), its step, period s, walking, phase, phase/s,
        #  travel m, weight, the step last advanced to]
        self.walk = [None, None, None, False, 0.0, 0.0, 0.0, 0.0, None]
        self._walk_out = None  # (step, channels) given last

    def _performer(self, step: int) -> dict:
        """The performer's channels as the tracker follows them: walking in place
        turned into a walk."""
        if self.walk_cycle is None or self.spec is None or self.spec.walk_in_place is None:
            return self.channels
        if self._walk_out is not None and self._walk_out[0] == step:
            return self._walk_out[1]
        self._walk_advance(step)
        out = self._walked()
        self._walk_out = (step, out)
        return out

    def _feet_gap(self, ch: dict) -> float | None:
        """m the first of ``tracking.feet`` is above the second in the pose ``ch``."""
        root = self.spec.root
        if root is None or root.angle not in ch or len(self.soles) < 2:
            return None
        chain, feet = self._feet_chain()
        angle = math.radians(ch[root.angle])
        fast = self.__dict__.get("_feet_kernel")
        if fast is not None:  # the compiled kernel (kd_kernel), the same arithmetic
            poses, index = fast.pose(ch, 0.0, 0.0, angle, math.cos(angle),
                                     math.sin(angle)), fast.index
            ys = []
            for foot, gx, gy in feet:
                i = 5 * index[foot]
                ys.append(poses[i + 1] + poses[i + 4] * gx + poses[i + 3] * gy)
            return ys[0] - ys[1]
        poses = channel_pose(chain, self.character.spec.root, (0.0, 0.0), angle,
                             math.cos(angle), math.sin(angle), ch)  # (not clamped)
        ys = []
        for foot, gx, gy in feet:
            _, oy, _, c, s = poses[foot]
            ys.append(oy + s * gx + c * gy)
        return ys[0] - ys[1]

    def _feet_chain(self) -> tuple[list, list]:
        """The joints from the root down to the first two of ``tracking.feet`` (the
        rest of the pose does not move them) with their channels (``channel_pose``), and
        each foot's centre of gravity: found once."""
        got = self.__dict__.get("_feet_rows")
        if got is None:
            feet = self.spec.feet[:2]
            needed, by_child = set(feet), {row[2]: row for row in self._chain}
            for foot in feet:
                link = foot
                while link in by_child:
                    link = by_child[link][1]
                    needed.add(link)
            chain = tracked_chain([row for row in self._chain if row[2] in needed],
                                  self.joints, {})  # each joint's channel, no limits
            bodies = self.character.bodies
            got = self._feet_rows = (chain, [(f, *bodies[f].center_of_gravity) for f in feet])
            if self.__dict__.get("_kern") is not None:  # (tracking_pull: the kernel runs)
                cs = self.character.spec
                self._feet_kernel = ChainPose(self._kern.kernel, chain,
                                              [link.name for link in cs.links], cs.root)
        return got

    def _cycle_lifts(self) -> tuple[float, float]:
        """The phases at which the example cycle lifts each foot (as the performer's are
        read), found once."""
        if getattr(self, "_lifts", None) is None:
            lift = self.spec.walk_in_place.lift
            found = [None, None]
            was = self._feet_gap(self.walk_cycle.at(0.0)) or 0.0
            for i in range(1, 201):
                gap = self._feet_gap(self.walk_cycle.at(i / 200)) or 0.0
                if found[0] is None and gap > lift >= was:
                    found[0] = i / 200
                if found[1] is None and gap < -lift <= was:
                    found[1] = i / 200
                was = gap
            near = found[0] if found[0] is not None else 0.0
            far = found[1] if found[1] is not None else (near + 0.5) % 1.0
            self._lifts = (near, far)
        return self._lifts

    def _walk_advance(self, step: int) -> None:
        spec, w = self.spec.walk_in_place, self.walk
        last_side, last_at, period, walking, phase, speed, travel, weight, at = w
        h = 0.0 if at is None or step <= at else (step - at) * self.dt
        gap = self._feet_gap(self.channels)
        if gap is not None:
            side = 0 if gap > spec.lift else 1 if gap < -spec.lift else None
            if side is not None and side != last_side:  # a step: the other foot lifted
                lo, hi = spec.steps
                if last_at is not None and lo <= (step - last_at) * self.dt <= hi \
                        and last_side is not None:
                    period = (step - last_at) * self.dt
                    target = self._cycle_lifts()[side]
                    if not walking:
                        walking, phase = True, target
                        speed = 0.5 / period
                    else:  # reach the other foot's lift in one period, from here
                        e = (target - phase + 0.5) % 1.0 - 0.5
                        speed = min(1.0, max(0.25, 0.5 + e)) / period
                last_side, last_at = side, step
        if walking and last_at is not None and (step - last_at) * self.dt > spec.stop_after:
            walking = False
        if spec.blend > 0.0:
            weight = min(1.0, weight + h / spec.blend) if walking else \
                max(0.0, weight - h / spec.blend)
        else:
            weight = 1.0 if walking else 0.0
        if weight > 0.0 and h > 0.0:
            cycle = self.walk_cycle
            new = phase + speed * h
            gone = cycle.travel(new % 1.0) - cycle.travel(phase) + cycle.stride * int(new)
            travel += weight * gone
            phase = new % 1.0
        self.walk = [last_side, last_at, period, walking, phase, speed, travel, weight, step]

    def _walked(self) -> dict:
        ch = self.channels
        weight, travel = self.walk[7], self.walk[6]
        rx = self.spec.root.x if self.spec.root is not None else "root.x"
        if weight <= 0.0 and travel == 0.0:
            return ch
        out = dict(ch)
        if weight > 0.0:  # (at_some's values, blended in: GaitCycle.blend_into)
            self.walk_cycle.blend_into(out, ch, self.walk[4], self.spec.walk_in_place.joints,
                                       weight)
        if rx in out:
            out[rx] = out[rx] + travel
        return out

    @property
    def walking(self) -> bool:
        return bool(self.walk[3]) if self.walk_cycle is not None else False

    def walk_state(self) -> list:
        return list(self.walk)

    def set_walk_state(self, state) -> None:
        self.walk = list(state) if state is not None else self.walk
        self._walk_out = None
