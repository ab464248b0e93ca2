"""Roles: names that mean one joint or link in one binding and another in the next.

A walk swaps its legs every step; rather than every pose and map written twice, the
interface names roles (``stance_hip`` is ``hip_near`` in the binding ``near`` and
``hip_far`` in ``far``) and each state selects a binding. This module resolves names
under the binding in force: joint and link names, the joint or link inside a sensor
name, a map's joints and frame, and the poses (compiled once per binding).
"""

from __future__ import annotations

from puppet.interface.poses import compile_poses


class RoleBinding:
    def __init__(self, spec):
        self.spec = spec
        self.binding: str | None = None
        self.rename = spec.renamer(None)
        self._poses: dict[str | None, dict] = {}
        self._renamers: dict = {}  # binding -> its renamer (made once, with its poses)

    def use(self, binding: str | None) -> dict:
        """Resolve as ``binding`` says from now on; the poses compiled for it."""
        self.binding = binding
        poses = self._poses.get(binding)
        if poses is None:
            self._renamers[binding] = self.spec.renamer(binding)
            poses = self._poses[binding] = compile_poses(self.spec.poses,
                                                         self._renamers[binding])
        self.rename = self._renamers[binding]
        return poses

    def sensor(self, sensor: str) -> str:
        """A sensor name with a role in it (angle.swing_thigh) as the binding means it;
        both links of ``lead.LINK.OTHER`` may be roles."""
        if sensor.startswith("lead."):
            roles, rename = self.spec.roles, self.rename
            parts = sensor.split(".")
            return ".".join([parts[0]] + [rename(p) if p in roles else p for p in parts[1:]])
        for role in self.spec.roles:
            if sensor.endswith("." + role):
                return sensor[:-len(role)] + self.rename(role)
        return sensor

    def names_role(self, m) -> bool:
        """Whether map ``m`` drives a joint through a role (its joint, joints, frame, or
        for a grid the poses' joints)."""
        roles = self.spec.roles
        if not roles:
            return False
        if getattr(m, "grid", None) is not None:
            poses = self.spec.poses
            return any(j in roles for row in m.grid for p in row
                       for j in poses[p].joints) or any(j in roles for j in m.joints or ())
        return m.joint in roles or m.frame in roles or any(j in roles for j in m.joints)

    def map(self, m):
        """Map ``m`` with its roles resolved (itself when the interface has none)."""
        if not self.spec.roles:
            return m
        r, rs = self.rename, self.sensor
        if getattr(m, "grid", None) is not None:
            update = {"x": rs(m.x), "y": rs(m.y)}
            if m.joints is not None:
                update["joints"] = [r(j) for j in m.joints]
            return m.model_copy(update=update)
        update = {"input": rs(m.input) if m.input is not None else None,
                  "joints": {r(j): g for j, g in m.joints.items()},
                  "frame": r(m.frame)}
        if m.joint is not None:
            update["joint"] = r(m.joint)
        return m.model_copy(update=update)
