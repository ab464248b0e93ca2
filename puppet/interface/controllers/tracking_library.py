"""A motion-library reaction of KD control (Zordan et al. 2005), the tracker's part that,
after a push, searches a motion library (``tracking.reaction.library``, the file
``puppet mocap library`` writes, ``puppet.data.motion_library``) for the window that
best matches the figure's state, follows it, then gives the figure back to the
performer. A mixin of ``Tracker``: it reads the tracker's spec, character and state.

The search runs ``library.after`` s after the push is judged (the push has shown in
the trunk's turning by then): each window's features - the trunk's (chest's) angle in
the world and its turning rate, the centre of mass's velocity, the joint angles - are
compared with the figure's own by a weighted sum of squared differences (the trunk
weighted high, ``library.weights``); the least wins, the first of equals on a tie. It
reads only the figure's state and the library's numbers, so a replay (or a restored
checkpoint) finds the same window. The window's channels are then followed - placed
where the figure's root is, blended in from the performer's over ``library.blend`` s -
to the window's end, and the tracker blends back to the performer over
``tracking.blend`` s (``_back_from``) while the reaction's pulls come back.
"""

from __future__ import annotations

import math


class LibraryReactions:
    library = None  # the MotionLibrary (the runtime loads it), or None

    def _library_case(self, case: str) -> bool:
        """Whether a reaction of ``case`` searches the library."""
        r = self.spec.reaction
        return (r is not None and r.library is not None and self.library is not None
                and case in r.library.cases and self.spec.root is not None)

    def _schedule_search(self, step: int) -> None:
        after = self.spec.reaction.library.after
        self.search_at = step + max(0, round(after / self.dt))
        self.lib = None

    def figure_features(self) -> tuple[float, ...]:
        """The figure's state as a window's features: trunk angle (rad), its turning
        rate (rad/s), the centre of mass's velocity (m/s), the library's joints' angles
        (rad, by their channels)."""
        from puppet.interface.controllers.tracking_getup import joint_degrees

        c, lib = self.character, self.library
        chest = c.bodies.get(lib.trunk_link) or c.bodies[c.spec.root]
        mass = vx = vy = 0.0
        for body in c.bodies.values():
            v = body.velocity
            mass += body.mass
            vx += body.mass * v.x
            vy += body.mass * v.y
        q = joint_degrees(c, self.joints)  # channel -> deg
        return (chest.angle, chest.angular_velocity, vx / mass, vy / mass,
                *(math.radians(q.get(name, 0.0)) for name in lib.joints))

    def search(self) -> tuple[int, float]:
        """The window (index) whose features are nearest the figure's, and the
        distance."""
        w = self.spec.reaction.library.weights
        me = self.figure_features()
        t0, s0, vx0, vy0 = me[:4]
        q0 = me[4:]
        best, best_d = 0, math.inf
        two_pi = 2 * math.pi
        for i, window in enumerate(self.library.windows):
            f = window.features
            da = f[0] - t0
            da -= two_pi * round(da / two_pi)
            d = (w.trunk * da * da + w.spin * (f[1] - s0) ** 2
                 + w.com * ((f[2] - vx0) ** 2 + (f[3] - vy0) ** 2))
            if d >= best_d:
                continue
            dq = 0.0
            for a, b in zip(f[4:], q0):
                dq += (a - b) * (a - b)
            d += w.joints * dq
            if d < best_d:
                best, best_d = i, d
        return best, best_d

    def _start_window(self, step: int) -> None:
        """Search now, and follow the window found from here."""
        self.search_at = None
        index, _ = self.search()
        first = self.library.channels_at(index, 0.0)
        rx = self.spec.root.x
        hx = self._hinge_world()[0]
        if self.x0 is None:
            self.x0 = hx - self.channels.get(rx, 0.0)
        offset = (hx - self.x0) - first.get(rx, 0.0)
        self.lib = [index, step, offset]
        self.searches = getattr(self, "searches", 0) + 1

    def _library_view(self, step: int, performer: dict) -> dict | None:
        """The channels to follow at ``step`` during a library reaction (None: none
        under way). The window's end starts the blend back to the performer."""
        if self.search_at is not None and step >= self.search_at:
            self._start_window(step)
        if self.lib is None:
            return None
        index, start, offset = self.lib
        lib = self.library
        t = (step - start) * self.dt
        came = lib.channels_at(index, t)
        rx = self.spec.root.x
        if rx in came:
            came[rx] += offset
        if t >= lib.duration:
            self.lib = None
            self.reaction = None  # the pulls whole again, back to the performer
            if self._down(came) and self.spec.reaction.get_up is not None:
                self.reaction = ("fall", step)  # down after all: up through the poses,
                self._start_get_up(step)  # not lifted by the pulls like strings
                return None
            self._back_from(came, step)
            return None
        blend = self.spec.reaction.library.blend
        if blend > 0.0 and t < blend:
            w = t / blend
            out = dict(performer)
            for name, v in came.items():
                u = performer.get(name, v)
                out[name] = u + (v - u) * w
            return out
        return came

    def _down(self, came: dict) -> bool:
        """Whether the figure is down at a window's end: its root tipped past 45 deg
        or its hips below 60% of the window's height."""
        hx, hy = self._hinge_world()
        ground = self.ground_at(hx) if self.ground_at is not None else None
        height = hy - (ground if ground is not None else 0.0)
        return not self.character.upright() or height < 0.6 * came.get(self.spec.root.y, 0.0)

    def _library_weight(self, step: int, low: float) -> float:
        """The pulls' weight in a library reaction: the case's (``low``) until the
        search, then to ``library.weight`` over ``library.blend``."""
        if self.lib is None:
            return low
        spec = self.spec.reaction.library
        t = (step - self.lib[1]) * self.dt
        w = 1.0 if spec.blend <= 0.0 or t >= spec.blend else t / spec.blend
        return low + (spec.weight - low) * w

    def library_status(self) -> str:
        if self.lib is None:
            return ""
        return f", reacting via library window {self.library.window_name(self.lib[0])}"

    def library_state(self) -> list:
        return [self.search_at, None if self.lib is None else list(self.lib),
                getattr(self, "searches", 0)]

    def set_library_state(self, state) -> None:
        self.search_at = state[0]
        self.lib = None if state[1] is None else list(state[1])
        self.searches = state[2]
