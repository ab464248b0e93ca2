"""IK reaches (the paper's "IK target select"): a chain's end follows a Hermite-eased
path to a target over a fixed duration, with IK re-solved every step, then holds.

The target is a fixed point (world, or the root link's frame at the moment of the
key), a scene prop's grasp point (followed as the prop moves; picked relative to what
a chain holds: the nearest, next or previous bar), or steered by two continuous inputs
(the mouse, or two channels) so a device moves a hand. A new reach of a chain replaces
its running one; a reach may grasp its target on arrival.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from math import hypot as _hypot

from puppet.interface.controllers.base import WAITED
from puppet.interface.ownership import JointOwners, Owner, reach_owner
from puppet.physics import kernel as _kernel
from puppet.physics.servo import GET_TARGET as _target
from puppet.physics.servo import SET_TARGET as _set_target

_OWNERS: dict[str, Owner] = {}  # chain -> its reach's owner (made once: a tick a step)


@dataclass
class Reach:
    """A running reach of ``chain``: from p0 (world, m) to its target over steps
    [start, start + steps], then held until ``end`` (None: until preempted)."""

    chain: str
    p0: tuple[float, float]
    target: list  # ["point", x, y] | ["prop", prop, point name] | ["steer", ...]
    start: int
    steps: int
    end: int | None
    grasp: bool = False
    tolerance: float = 0.04
    rigid: bool = False  # the grasp holds the end link's angle too
    max_torque: float | None = None

    def to_state(self) -> list:
        return [self.chain, list(self.p0), list(self.target), self.start, self.steps,
                self.end, self.grasp, self.tolerance, self.rigid, self.max_torque]

    @classmethod
    def from_state(cls, s) -> Reach:
        return cls(s[0], tuple(s[1]), list(s[2]), *s[3:])


class ReachController:
    BUSY = "reaches"

    def __init__(self, chains, character, sim, owners: JointOwners, servos, grasps,
                 read_input, dt: float):
        self.chains = chains
        self.character = character
        self.sim = sim
        self.owners_table = owners
        self.servos = servos
        self.grasps = grasps  # the GraspController, for reaches that grasp on arrival
        self.read_input = read_input  # (name, default) -> an input's value now (steering)
        self.dt = dt
        self.reaches: dict[str, Reach] = {}
        # the compiled kernel's aim and solve of a two-link chain (``pk_reach_aim``,
        # ``pk_reach_set``: the arithmetic of ``tick`` and ``Chain.solve``), or None
        kern = _kernel.get()
        self._pk = None if kern is None else (
            kern.lib.pk_reach_aim, kern.lib.pk_reach_set, kern.ffi.NULL,
            kern.ffi.new("double[4]"), kern.ffi.new("double[2]"), kern)
        self._aims: dict = {}  # chain -> its reach's arguments for the kernel (_aim_args)
        self._plan = None  # what ``tick`` runs (``_planned``), until a reach starts or ends

    # -- targets -------------------------------------------------------------------
    def _root_to_world(self, p) -> tuple[float, float]:
        root = self.character.bodies[self.character.spec.root]
        w = root.local_to_world(p)
        return (w[0], w[1])

    def target_now(self, target: list) -> tuple[float, float]:
        """Where a target is at this moment (world, m)."""
        kind = target[0]
        if kind == "point":
            return (target[1], target[2])
        if kind == "prop":
            return self.sim.props[target[1]].point_world(target[2])
        _, xn, yn, (x0, x1), (y0, y1), (tx0, tx1), (ty0, ty1), frame = target
        read = self.read_input
        u = (read(xn, 0.5 * (x0 + x1)) - x0) / (x1 - x0)
        v = (read(yn, 0.5 * (y0 + y1)) - y0) / (y1 - y0)
        u, v = min(1.0, max(0.0, u)), min(1.0, max(0.0, v))
        p = (tx0 + u * (tx1 - tx0), ty0 + v * (ty1 - ty0))
        return self._root_to_world(p) if frame == "root" else p

    def pick_prop_point(self, spec, chain: str) -> str:
        """The name of the prop's grasp point ``spec`` picks for ``chain``: counted
        ``offset`` places from the point nearest where chain ``of`` (default ``chain``)
        holds, or from the point nearest its end if it holds nothing."""
        prop = self.sim.props[spec.prop]
        names = list(prop.points)
        ref = self.grasps.held.get(spec.of or chain)
        if ref is None:
            ref = self.chains[spec.of or chain].end_world(self.character)
        here = min(range(len(names)), key=lambda i: math.dist(prop.point_world(names[i]), ref))
        return names[min(len(names) - 1, max(0, here + spec.offset))]

    def let_go(self, which: str) -> None:
        """A release of chain ``which`` ("all": every chain): its running reach goes
        on but no longer grasps (else it would take hold again at once)."""
        for name, reach in self.reaches.items():
            if which in ("all", name):
                reach.grasp = False

    # -- running -------------------------------------------------------------------
    def start(self, r, now: int) -> None:
        chain = self.chains[r.chain]
        owner = reach_owner(r.chain)
        self.owners_table.drop(owner)
        if r.target is not None:
            p = self._root_to_world(r.target) if r.frame == "root" else tuple(r.target)
            target = ["point", p[0], p[1]]
        elif r.point is not None:
            target = ["prop", r.point.prop, self.pick_prop_point(r.point, r.chain)]
        else:
            s = r.steer
            target = ["steer", s.x, s.y, list(s.x_from), list(s.y_from), list(s.x_to),
                      list(s.y_to), r.frame]
        steps = max(1, round(r.duration / self.dt))
        end = None if r.steer is not None else now + steps + round(r.hold / self.dt)
        self.reaches[r.chain] = Reach(r.chain, chain.end_world(self.character), target, now,
                                      steps, end, r.grasp, r.tolerance, r.rigid,
                                      r.max_torque)
        self._plan = None
        self.owners_table.claim(chain.joints, owner)

    def tick(self, step: int) -> str | None:
        """Each reach's point on its way (or held), its chain solved for it and the
        joints it still owns written; a reach that grasps tries its grasp. WAITED when
        it only wrote targets: no reach ended or lost its joints, and no grasp was made
        (its next wake-up is the next step, as before). The ladder runs this at every
        step: with the kernel and two-link chains, each reach's lookups are made once
        (``_planned``) and a step is its two kernel calls and its owner checks, the
        arithmetic and the order of ``_tick_general``'s."""
        if not self.reaches:
            return None
        plan = self._plan
        if plan is None or plan[0] is not self.character.bodies:
            plan = self._plan = self._planned()
        if plan[1] is None:
            return self._tick_general(step)
        table = self.owners_table.table
        get = table.get
        aim, solve, null, out, q, _ = self._pk
        sim = self.sim
        changed = False
        for name, reach, owner, j0, j1, start, args, params, spring0, spring1 in plan[1]:
            own0, own1 = get(j0) == owner, get(j1) == owner
            if not (own0 or own1) and owner not in table.values():  # (holds_any)
                self._end(name, None)
                changed = True
                continue
            if args is None:  # a steered target: its point read now (as _aim_args does)
                args = self._aim_args(name, reach, self.chains[name], "steer")[2]
            aim(step - start, *args)
            d0, d1 = out[0], out[1]
            solve(params, d0, d1, _hypot(d0, d1), spring0 if own0 else null, spring1, own1, q)
            if reach.grasp and sim is not None and name not in sim.grasps:
                changed = self._grasp(name, reach, (out[2], out[3])) or changed
            end = reach.end
            if end is not None and step >= end:
                self._end(name, owner)
                changed = True
        return None if changed or not self.reaches else WAITED

    def _planned(self) -> tuple:
        """(the bodies, per reach its name, Reach, owner, two joints, start, the kernel's
        aim arguments (None: a steered target's, read at each step), its chain's numbers
        and its joints' springs), or (the bodies, None) when a reach needs
        ``_tick_general`` (no kernel, a chain of other than two links)."""
        bodies = self.character.bodies
        if self._pk is None:
            return bodies, None
        rows = []
        for name, reach in self.reaches.items():
            chain = self.chains[name]
            if len(chain.joints) != 2:
                return bodies, None
            kind = reach.target[0]
            args = self._aim_args(name, reach, chain, kind)
            rows.append((name, reach, _OWNERS.get(name) or _OWNERS.setdefault(
                name, reach_owner(name)), *chain.joints, reach.start,
                None if kind == "steer" else args[2], *args[3:]))
        return bodies, tuple(rows)

    def _grasp(self, name: str, reach: Reach, goal) -> bool:
        """A reach that grasps on arrival tries its grasp at ``goal`` (its target's
        point now): whether it made one."""
        target = reach.target
        kind = target[0]
        hold = (reach.tolerance, reach.rigid, reach.max_torque)
        if kind == "point":
            return self.grasps.try_grasp(name, [goal], None, *hold)
        if kind == "prop":  # only the point aimed at: not the bar let go of
            return self.grasps.try_grasp(name, [goal], target[1], *hold)
        if self.sim.props:
            return self.grasps.try_grasp(name, None, "any", *hold)
        return False

    def _end(self, name: str, owner: Owner | None) -> None:
        """Reach ``name`` ends (``owner``: its joints let go, else it owned none)."""
        if owner is not None:
            self.owners_table.drop(owner)
        del self.reaches[name]
        self._aims.pop(name, None)  # (its arguments keep the bodies they were for)
        self._plan = None

    def _tick_general(self, step: int) -> str | None:
        """``tick`` for any reach (a chain of other than two links, a steered
        target, the pure-Python path): the reference the fast path is tested against."""
        servos, owners = self.servos, self.owners_table
        table, character = owners.table, self.character
        sim = self.sim
        pk = self._pk
        aims = self._aims
        out = None if pk is None else pk[3]
        changed = False
        for name, reach in list(self.reaches.items()):
            owner = _OWNERS.get(name) or _OWNERS.setdefault(name, reach_owner(name))
            chain = self.chains[name]
            joints = chain.joints
            get = table.get
            two = len(joints) == 2
            if two:  # (a reach claims its chain's joints: what it owns is among them)
                j0, j1 = joints
                own0, own1 = get(j0) == owner, get(j1) == owner
                owned = own0 or own1
            else:
                owned = [j for j in joints if get(j) == owner]
            if not owned and not owners.holds_any(owner):
                self._end(name, None)
                changed = True
                continue
            target = reach.target
            kind = target[0]
            if two and pk is not None:  # the kernel: the arithmetic below, in C
                aim, solve, null, out, q, _ = pk
                args = aims.get(name)  # (for this reach and these bodies: _aim_args)
                if args is None or args[0] is not reach or args[1] is not character.bodies:
                    args = aims[name] = self._aim_args(name, reach, chain, kind)
                aim(step - reach.start, *args[2])
                d0, d1 = out[0], out[1]
                solve(args[3], d0, d1, _hypot(d0, d1), args[4] if own0 else null, args[5],
                      own1, q)
                goal = out  # (its goal's x, y: out[2], out[3], read by a grasp below)
            else:
                goal = (target[1], target[2]) if kind == "point" else self.target_now(target)
                u = (step - reach.start) / reach.steps  # hermite(u), inlined
                u = min(1.0, max(0.0, u))
                h = u * u * (3.0 - 2.0 * u)
                p0 = reach.p0
                point = (p0[0] + h * (goal[0] - p0[0]), p0[1] + h * (goal[1] - p0[1]))
                if two:  # the closed form reads the bend it keeps, only
                    spring = servos[j1].spring._constraint
                    q0, q1 = chain.solve(character, point, (None, _target(spring)))
                    if own0:
                        _set_target(servos[j0].spring._constraint, q0)
                    if own1:
                        _set_target(spring, q1)
                else:
                    q = chain.solve(character, point,
                                    [_target(servos[j].spring._constraint) for j in joints])
                    for joint, angle in zip(joints, q):
                        if joint in owned:
                            _set_target(servos[joint].spring._constraint, angle)
            if reach.grasp and sim is not None and name not in sim.grasps:
                # (try_grasp does nothing for a chain that holds already: not asked)
                changed = self._grasp(name, reach, (out[2], out[3]) if goal is out else goal) \
                    or changed
            if reach.end is not None and step >= reach.end:
                self._end(name, owner)
                changed = True
        return None if changed or not self.reaches else WAITED

    def _aim_args(self, name: str, reach: Reach, chain, kind: str) -> tuple:
        """(reach, the bodies, pk_reach_aim's arguments after the steps done, the
        chain's numbers for pk_reach_set, its joints' springs): what stays while the
        reach runs on these bodies (a re-seat re-binds them, and the props'), but a
        steered target's point, read at every step (then not kept: its bodies None)."""
        aim, _, null, out, _, kern = self._pk
        sim, character, servos = self.sim, self.character, self.servos
        target = reach.target
        if kind == "point":
            body, gx, gy = null, target[1], target[2]
        elif kind == "prop":
            prop = sim.props[target[1]]
            body, (gx, gy) = prop.body._body, prop.points[target[2]]
        else:
            body, (gx, gy) = null, self.target_now(target)
        ax, ay = chain.anchor
        p0 = reach.p0
        j0, j1 = chain.joints
        return (reach, None if kind == "steer" else character.bodies,
                (character.bodies[chain.parent_link]._body, ax, ay, body, gx, gy, p0[0], p0[1],
                 reach.steps, out),
                chain.two_params(kern), servos[j0].spring._constraint,
                servos[j1].spring._constraint)

    def next_wakeup(self, earliest: int) -> int | None:
        # every step, on the way and holding: at the control rate (60 Hz) the ladder
        # climb passed 9-10 of 20 human playtest tries against its bar of 14 (17 with
        # the IK solved every step), so the rate is the feat's, not a setting to change
        # under it (docs/benchmarks.md)
        return earliest if self.reaches else None

    def owners(self) -> set[Owner]:
        return {reach_owner(n) for n in self.reaches}

    def get_state(self):
        return {n: r.to_state() for n, r in self.reaches.items()}

    def set_state(self, state) -> None:
        self.reaches = {n: Reach.from_state(r) for n, r in state.items()}
        self._aims.clear()
        self._plan = None

    def adopt(self, old: ReachController, same, now: int) -> set[Owner]:
        self.reaches = {n: Reach.from_state(r.to_state()) for n, r in old.reaches.items()
                        if same("chain", n)}
        self._plan = None
        return {reach_owner(n) for n in self.reaches}

    def stop(self) -> None:
        self.reaches = {}
        self._aims.clear()
        self._plan = None
