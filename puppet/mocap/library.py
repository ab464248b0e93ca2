"""Index a folder of BVH clips into a motion library (Zordan et al. 2005): the file
``puppet mocap library FOLDER`` writes and ``tracking.reaction.library`` searches after
an impact (its format: ``puppet.data.motion_library``).

Each clip is read through the shipped mapping that names all its joints (as ``play
--mocap`` picks one) or, failing that, the humanoid rig recognised in it
(``puppet.mocap.rigs``): any skeleton, no mapping written by hand. Its channels are
sampled at ``rate`` frames a second and cut into windows of ``window`` s every ``hop``
s; each window (and its mirror image, near and far swapped, with ``mirror``) gets the
features a figure's state is matched against: the trunk's angle in the world and its
turning rate, the centre of mass's velocity (the performed pose on the character's
own links and masses), the joint angles. A clip that cannot be read or recognised is
skipped with a one-line note; a folder with none left is a ``DataError``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from puppet.data.errors import DataError
from puppet.data.motion_library import FORMAT
from puppet.interface.controllers.kd_pull import joint_chain, performed_pose
from puppet.physics.kinematics import joint_order

ROOT_CHANNELS = ("root.x", "root.y", "root.angle", "clearance")


def clip_mapping(bvh, character):
    """(mapping, where it came from) for a clip: a shipped mapping naming all its
    joints that fits the character, else its recognised humanoid rig's."""
    from puppet.data.mappings import channel_problem
    from puppet.mocap.info import matching_mappings
    from puppet.mocap.rigs import recognise

    joints = [j.name for j in character.joints]
    for name, spec in matching_mappings(bvh):
        if spec.character == character.name and \
                channel_problem(spec, joints, character.name) is None:
            return spec, name
    rig = recognise(bvh, character)
    return rig.mapping, "recognised rig"


class _Figure:
    """The character's links, for the performed pose's trunk and centre of mass."""

    def __init__(self, spec):
        import pymunk

        from puppet.physics.character import Character

        c = Character(spec)
        space = pymunk.Space()
        c.add_to(space)  # (the bodies' masses come from their shapes in a space)
        self.spec = spec
        self.chain = joint_chain(joint_order(spec))
        self.mass = {n: b.mass for n, b in c.bodies.items()}
        self.cog = {n: tuple(b.center_of_gravity) for n, b in c.bodies.items()}
        self.total = sum(self.mass.values())
        self.trunk = "chest" if "chest" in c.bodies else spec.root

    def state(self, ch: dict, hinge_at: str) -> tuple[float, float, float]:
        """(trunk angle, centre of mass x, y) of the performed pose ``ch`` (deg, m)."""
        angle = math.radians(ch["root.angle"])
        cos, sin = math.cos(angle), math.sin(angle)
        ax, ay = self.spec.joint(hinge_at).anchor
        origin = (ch["root.x"] - (cos * ax - sin * ay), ch["root.y"] - (sin * ax + cos * ay))
        q = {name: math.radians(v) for name, v in ch.items() if name not in ROOT_CHANNELS}
        poses = performed_pose(self.chain, self.spec.root, origin, angle, cos, sin, q)
        x = y = 0.0
        for name, (ox, oy, _, c, s) in poses.items():
            gx, gy = self.cog[name]
            m = self.mass[name]
            x += m * (ox + c * gx - s * gy)
            y += m * (oy + s * gx + c * gy)
        return poses[self.trunk][2], x / self.total, y / self.total


def index_folder(folder, character_name: str = "biped", rate: float = 30.0,
                 window: float = 1.0, hop: float = 0.1, mirror: bool = True,
                 notes: list | None = None) -> dict:
    """The library (the JSON document) of every ``*.bvh`` directly in ``folder``, in
    name order. ``notes`` collects one line per clip skipped."""
    from puppet.data.catalog import load_character_named
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.retarget import retarget_clip

    folder = Path(folder)
    if not folder.is_dir():
        raise DataError(str(folder), None, None, "not a folder; expected a folder of .bvh "
                                                 "clips")
    paths = sorted(p for p in folder.iterdir() if p.suffix.lower() == ".bvh" and p.is_file())
    if not paths:
        raise DataError(str(folder), None, None, "no .bvh clips in this folder")
    character, _ = load_character_named(character_name)
    figure = _Figure(character)
    actuated = [j.name for j in character.actuated]
    notes = notes if notes is not None else []
    taken = []
    for path in paths:
        try:
            bvh = read_bvh(path)
            mapping, source = clip_mapping(bvh, character)
            clip = retarget_clip(bvh, mapping, str(path))
        except DataError as exc:
            notes.append(f"skipped {path.name}: {exc.message}")
            continue
        if clip.duration < window or any(n not in clip.channels for n in ROOT_CHANNELS[:3]):
            notes.append(f"skipped {path.name}: shorter than a window ({clip.duration:.2f} "
                         f"s)" if clip.duration < window else
                         f"skipped {path.name}: its mapping gives no root channels")
            continue
        hinge_at = "hip_near" if "hip_near" in actuated else actuated[0]  # the hips' hinge
        taken.append((path, source, clip, hinge_at))
    if not taken:
        raise DataError(str(folder), None, None,
                        f"no clip could be used ({len(paths)} .bvh: "
                        f"{'; '.join(notes)[:200]})")
    joints = [j for j in actuated if all(j in c.channels for _, _, c, _ in taken)]
    channels = [n for n in ROOT_CHANNELS if all(n in c.channels for _, _, c, _ in taken)]
    channels += joints
    pairs = [[a, a[:-5] + "_far"] for a in channels
             if a.endswith("_near") and a[:-5] + "_far" in channels]
    swap = {a: b for a, b in pairs} | {b: a for a, b in pairs}
    span = max(2, round(window * rate) + 1)
    step = max(1, round(hop * rate))
    clips, windows = [], []
    for ci, (path, source, clip, hinge_at) in enumerate(taken):
        count = int(math.floor(clip.duration * rate)) + 1
        rows, last = [], {}
        for k in range(count):
            values = clip.at(k / rate)
            last.update(values)
            rows.append([round(float(last.get(n, 0.0)), 5) for n in channels])
        clips.append({"name": path.stem, "mapping": source, "frames": rows})
        for mirrored in ((False, True) if mirror and pairs else (False,)):
            names = [swap.get(n, n) if mirrored else n for n in channels]
            states = [figure.state(dict(zip(names, row)), hinge_at) for row in rows]
            for start in range(0, count - span + 1, step):
                before, after = max(0, start - 1), min(count - 1, start + 1)
                h = (after - before) / rate
                a0, a1 = states[before][0], states[after][0]
                spin = math.remainder(a1 - a0, 2 * math.pi) / h
                vx = (states[after][1] - states[before][1]) / h
                vy = (states[after][2] - states[before][2]) / h
                row = dict(zip(names, rows[start]))
                windows.append({"clip": ci, "start": start, "mirrored": mirrored,
                                "trunk": round(states[start][0], 6), "spin": round(spin, 6),
                                "com": [round(vx, 6), round(vy, 6)],
                                "q": [round(math.radians(row[j]), 6) for j in joints]})
    return {"format": FORMAT, "version": 1,
            "description": f"motion library of {len(clips)} clip(s) from {folder.name}/ "
                           f"for {character.name}: {len(windows)} windows of {window:g} s",
            "character": character.name, "trunk_link": figure.trunk, "rate": rate,
            "window": window, "hop": hop, "channels": channels, "joints": joints,
            "mirror": pairs, "clips": clips, "windows": windows}


def write_library(library: dict, path) -> None:
    Path(path).write_text(json.dumps(library, separators=(",", ":")) + "\n", encoding="utf-8")
