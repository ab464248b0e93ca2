"""A performance as motion for animators: ``puppet replay LOG --export-motion OUT``.

The log is replayed headless (the same bits as ``puppet replay``) and sampled at a
chosen frame rate: the root link's position and angle and every joint's angle (the
child link's angle minus the parent's, counter-clockwise positive, as in the
character file). It is written as

* a BVH (``.bvh``): a planar hierarchy named after the character's links, the root
  link the BVH root, each joint a BVH joint at its anchor (metres, x forward, y up,
  rotations about z; see ``puppet.mocap.bvh.write_planar_bvh``), which Blender's
  importer reads (File > Import > Motion Capture (.bvh));
* or a CSV (``.csv``): one row per frame under a header row, ``frame, time_s,
  root_x_m, root_y_m, root_angle_deg`` and ``JOINT_deg`` for every joint.

The root's position is its model origin (where ``Character.place`` puts it), so the
BVH's forward kinematics lands every joint on its anchor in the simulation. Angles
accumulate (a back flip's root goes from 0 to 360 degrees, never jumping back), as an
animator's curves should. A rewind in the log keeps the history that was kept, as
replays do.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from puppet.data.catalog import short_path
from puppet.data.characters import CharacterSpec
from puppet.mocap.bvh import PlanarJoint, write_planar_bvh
from puppet.session import Session
from puppet.timeline.log import Log, read_log
from puppet.timeline.replay import apply_log, new_session, setup_for_log

FORMATS = (".bvh", ".csv")


@dataclass
class Motion:
    """Sampled frames: ``t`` (s), ``step``, ``root_xy`` (m), ``root_angle`` (rad),
    ``joint_angle`` (frames, joints; rad, ``joints`` order)."""

    character: CharacterSpec
    fps: float
    step: np.ndarray
    t: np.ndarray
    root_xy: np.ndarray
    root_angle: np.ndarray
    joints: list[str]
    joint_angle: np.ndarray
    final_hash: str = ""

    @property
    def frames(self) -> int:
        return len(self.t)


def sample_motion(log: str | Path | Log, fps: float, until_step: int | None = None,
                  allow_truncated: bool = False, as_recorded: bool = False) -> Motion:
    """Replay ``log`` headless and sample frame k at the step nearest k / fps s."""
    if not fps > 0:
        raise ValueError("fps must be positive")
    log = log if isinstance(log, Log) else read_log(log, allow_truncated)
    setup, _ = setup_for_log(log, as_recorded)
    session = new_session(log, setup)
    dt = session.sim.dt
    spec = session.character.spec
    joints = [j.name for j in spec.joints]
    rows: dict[int, tuple] = {}  # step -> sample, in step order

    def wanted(step: int) -> bool:  # is ``step`` the nearest step to a frame time?
        k = round(step * dt * fps)
        return round(k / fps / dt) == step

    def tick(s: Session) -> None:
        step = s.steps
        if rows and step <= next(reversed(rows)):  # a rewind: drop the abandoned branch
            for old in [k for k in rows if k >= step]:
                del rows[old]
        if wanted(step):
            rows[step] = _sample(s, joints)

    tick(session)
    apply_log(session, log, until_step, 1, tick)
    steps = np.array(list(rows), dtype=np.int64)
    data = list(rows.values())
    return Motion(spec, fps, steps, steps * dt,
                  np.array([r[0] for r in data], dtype=float).reshape(-1, 2),
                  np.array([r[1] for r in data], dtype=float),
                  joints, np.array([r[2] for r in data], dtype=float).reshape(-1, len(joints)),
                  session.sim.state_hash())


def _sample(session: Session, joints: list[str]) -> tuple:
    c = session.character
    root = c.bodies[c.spec.root]
    angles = [c.bodies[j.child].angle - c.bodies[j.parent].angle for j in c.spec.joints]
    return ((root.position.x, root.position.y), root.angle, angles)


# -- the hierarchy ----------------------------------------------------------------------
def planar_hierarchy(spec: CharacterSpec) -> list[PlanarJoint]:
    """The character as a planar BVH hierarchy: one joint per link (named after it),
    at its joint's anchor, the offsets in metres from the parent's anchor (the root's
    pivot is the model origin); a link with no children ends at its farthest point."""
    pivot = {spec.root: (0.0, 0.0)}
    parent_of: dict[str, str] = {}
    for j in spec.joints:
        pivot[j.child] = tuple(j.anchor)
        parent_of[j.child] = j.parent
    has_children = set(parent_of.values())
    out = [PlanarJoint(spec.root, None, (0.0, 0.0),
                       None if spec.root in has_children else _far(spec, spec.root, (0, 0)))]
    for j in spec.joints:  # the spec lists a joint after its parent's (validated tree)
        px, py = pivot[j.parent]
        ax, ay = j.anchor
        end = None if j.child in has_children else _far(spec, j.child, (ax, ay))
        out.append(PlanarJoint(j.child, j.parent, (ax - px, ay - py), end))
    return _parents_first(out)


def _parents_first(joints: list[PlanarJoint]) -> list[PlanarJoint]:
    done, ordered, pending = set(), [], list(joints)
    while pending:
        for j in list(pending):
            if j.parent is None or j.parent in done:
                ordered.append(j)
                done.add(j.name)
                pending.remove(j)
    return ordered


def _far(spec: CharacterSpec, link: str, pivot: tuple[float, float]) -> tuple[float, float]:
    """The point of ``link``'s shapes farthest from ``pivot`` (model frame), relative
    to it: where the link's last bone ends."""
    points: list[tuple[float, float]] = []
    for s in next(lk for lk in spec.links if lk.name == link).shapes:
        if s.type == "box":
            w, h = s.size
            a = math.radians(s.angle)
            c, sn = math.cos(a), math.sin(a)
            points += [(s.center[0] + c * x - sn * y, s.center[1] + sn * x + c * y)
                       for x, y in ((-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2),
                                    (-w / 2, h / 2))]
        elif s.type == "circle":
            points.append(tuple(s.center))
        elif s.type == "segment":
            points += [tuple(s.a), tuple(s.b)]
        else:
            points += [tuple(p) for p in s.points]
    far = max(points, key=lambda p: math.hypot(p[0] - pivot[0], p[1] - pivot[1]))
    return (far[0] - pivot[0], far[1] - pivot[1])


# -- writing ----------------------------------------------------------------------------
def write_motion(motion: Motion, path: str | Path) -> None:
    """Write ``motion`` as BVH or CSV, by the suffix of ``path`` (its folder is created
    if missing, as a video's, a plot's, a screenshot's and a log's are)."""
    suffix = Path(path).suffix.lower()
    if suffix in FORMATS:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".bvh":
        joints = planar_hierarchy(motion.character)
        col = {name: i for i, name in enumerate(motion.joints)}
        child_joint = {j.child: j.name for j in motion.character.joints}
        angles = np.empty((motion.frames, len(joints)))
        for k, pj in enumerate(joints):
            angles[:, k] = (motion.root_angle if pj.parent is None
                            else motion.joint_angle[:, col[child_joint[pj.name]]])
        write_planar_bvh(path, joints, motion.root_xy, np.degrees(angles), 1.0 / motion.fps)
    elif suffix == ".csv":
        with open(path, "w", newline="", encoding="utf-8") as f:
            out = csv.writer(f)
            out.writerow(["frame", "time_s", "root_x_m", "root_y_m", "root_angle_deg"]
                         + [f"{j}_deg" for j in motion.joints])
            deg = np.degrees(motion.joint_angle)
            root = np.degrees(motion.root_angle)
            for k in range(motion.frames):
                out.writerow([k, f"{motion.t[k]:.6f}", f"{motion.root_xy[k, 0]:.6f}",
                              f"{motion.root_xy[k, 1]:.6f}", f"{root[k]:.6f}"]
                             + [f"{v:.6f}" for v in deg[k]])
    else:
        raise ValueError(f"cannot write '{suffix}' motion; use one of {', '.join(FORMATS)}")


def export_motion_command(args) -> int:
    """``puppet replay LOG --headless --export-motion OUT.bvh|OUT.csv [--fps N]``.
    The command line (``puppet.commands.replay``) has checked OUT (a file name ending in .bvh or
    .csv, not a folder) before this runs; a missing folder is created, as --video,
    --plot, --screenshot and --record do."""
    import sys

    from puppet.data.errors import UsageError
    from puppet.timeline.replay import find_log

    if len(args.logs) != 1:
        raise UsageError("--export-motion takes one log")
    out = Path(args.export_motion)
    if out.suffix.lower() not in FORMATS:
        raise UsageError(f"--export-motion {out}: cannot write '{out.suffix}' files; "
                         f"use {' or '.join(FORMATS)}")
    if not args.fps > 0:
        raise UsageError("--fps must be positive")
    path = find_log(args.logs[0])
    log = read_log(path, args.allow_truncated)
    from puppet.timeline.report import until_note

    _, warnings = setup_for_log(log, args.as_recorded)
    note = until_note(log, args.until_step)  # past the log's end: it runs on, no input
    for w in warnings + ([note] if note else []):
        print(w, file=sys.stderr)
    motion = sample_motion(log, args.fps, args.until_step, args.allow_truncated,
                           args.as_recorded)
    try:
        write_motion(motion, out)
    except OSError as exc:  # a read-only folder, a full disk: one line, not a traceback
        raise UsageError(f"--export-motion {short_path(out)}: cannot write: "
                         f"{exc.strerror or exc}") from None
    same = ("" if log.end_hash is None or args.until_step is not None
            else " (same end as recorded)" if motion.final_hash == log.end_hash
            else f" (recorded {log.end_hash}: DIFFERENT)")
    print(f"wrote {out}: {motion.frames} frames at {motion.fps:g} fps, "
          f"{motion.t[-1]:.3f} s of {motion.character.name}, ending in state "
          f"{motion.final_hash}{same}")
    return 0
