"""The VMC protocol (https://protocol.vmc.info), performer to marionette: decode and
encode.

Messages used (others under ``/VMC/`` are valid and ignored, counted as ``ignored``):

* ``/VMC/Ext/Root/Pos name px py pz qx qy qz qw [sx sy sz ox oy oz]``: the model's
  root transform in the world (the v2.1 scale and offset are accepted, not applied);
* ``/VMC/Ext/Bone/Pos name px py pz qx qy qz qw``: a humanoid bone's local transform
  (Unity ``HumanBodyBones`` name, position and rotation in its parent's frame);
* ``/VMC/Ext/T time``: the sender's time in seconds (frames must go forward);
* ``/VMC/Ext/OK ...``: the frame is complete (so is it at the end of a bundle).

All in Unity's frame: left-handed, Y up, metres. A bone keeps its last local
transform until it is sent again; a frame's points are the world positions of every
bone received so far (``puppet.mocap.unity.world_positions``), named by bone, in
Unity's frame (a mapping says ``handedness: left``, ``up: y``).

Senders as people use them:

* **rotation only**: when every bone but the hips is sent at position 0 0 0 (VRM-based
  webcam trackers send rotations alone, for the receiver's own avatar), each is placed
  where the avatar of ``assets/mocap/vmc-avatar.yaml`` has it (the hips too, if sent at
  0 0 0) - a T-pose with the biped's proportions, all rotations the identity at rest,
  as VRM's normalised bones are - so the rotations give positions through the avatar's
  bone lengths;
* **a frame in several bundles** with one ``/VMC/Ext/T``: each bundle after the first
  goes on with the frame (``Counts.continued``), not dropped as ``stale``.
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Annotated

from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
from pythonosc.osc_message_builder import OscMessageBuilder

from puppet.data.ranges import Num
from puppet.data.validate import Meta, Spec, validate
from puppet.mocap import unity
from puppet.mocap.osc import MAX_POSITION, Decoder, Drop, Frame, bounded, frame_time, text

AVATAR = Path(__file__).resolve().parents[2] / "assets" / "mocap" / "vmc-avatar.yaml"

DEFAULT_PORT = 39539
ROOT = "/VMC/Ext/Root/Pos"
BONE = "/VMC/Ext/Bone/Pos"
TIME = "/VMC/Ext/T"
OK = "/VMC/Ext/OK"
QUAT_NORM = (0.9, 1.1)  # a rotation's quaternion length outside this is garbage (senders
# write unit quaternions as float32: 1 within 1e-6; a length of 2 is no rotation)


def _transform(args: list, what: str) -> tuple[unity.Vec, unity.Quat]:
    p = tuple(bounded(v, f"{what} position", MAX_POSITION) for v in args[0:3])
    q = tuple(bounded(v, f"{what} rotation", 2.0) for v in args[3:7])
    norm = sum(c * c for c in q) ** 0.5
    if not QUAT_NORM[0] <= norm <= QUAT_NORM[1]:
        raise Drop("out_of_range", f"{what} rotation: a quaternion of length {norm:.3g} "
                                   f"(expected 1, a unit quaternion)")
    return p, unity.normalised(q)  # type: ignore[arg-type]


class VmcDecoder(Decoder):
    format = "vmc"
    default_port = DEFAULT_PORT

    def __init__(self):
        super().__init__()
        self.root: tuple[unity.Vec, unity.Quat] = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
        self.bones: dict[str, tuple[unity.Vec, unity.Quat]] = {}
        self._bones: dict[str, tuple[unity.Vec, unity.Quat]] = {}  # staged for a frame
        self._root: tuple[unity.Vec, unity.Quat] | None = None
        self._time: float | None = None
        self._dirty = False

    def message(self, address: str, args: list) -> Frame | None:
        if address == BONE:
            if len(args) != 8:
                raise Drop("bad_arguments", f"{BONE}: 8 arguments expected, got {len(args)}")
            name = text(args[0], f"{BONE} name")
            if name not in unity.PARENTS:
                raise Drop("bad_arguments", f"{BONE}: '{name[:40]}' is not a humanoid bone")
            self._bones[name] = _transform(args[1:], name)
            self._dirty = True
        elif address == ROOT:
            if len(args) not in (8, 14):
                raise Drop("bad_arguments", f"{ROOT}: 8 or 14 arguments expected, "
                                            f"got {len(args)}")
            text(args[0], f"{ROOT} name")
            root = _transform(args[1:8], "root")
            for v in args[8:]:
                bounded(v, "root scale/offset", MAX_POSITION)
            self._root = root
            self._dirty = True
        elif address == TIME:
            if len(args) != 1:
                raise Drop("bad_arguments", f"{TIME}: 1 argument expected, got {len(args)}")
            self._time = frame_time(args[0])
        elif address == OK:
            return self._frame()
        elif address.startswith("/VMC/"):
            self.counts.ignored += 1
        else:
            raise Drop("unknown_address", f"'{address[:40]}' is not a VMC address")
        return None

    def bundle_end(self) -> Frame | None:
        return self._frame()

    def _frame(self) -> Frame | None:
        if not self._dirty:
            self._time = None
            return None
        return Frame(time=self._time)

    def rejected(self) -> None:
        self._bones.clear()
        self._root, self._time, self._dirty = None, None, False

    def committed(self) -> None:
        self.bones.update(self._bones)
        if self._root is not None:
            self.root = self._root
        self.rejected()

    def novel(self, frame: Frame) -> bool:
        """A bundle at the last frame's time with bones (or a root) it had otherwise:
        the frame's next part."""
        return (any(self.bones.get(n) != v for n, v in self._bones.items())
                or (self._root is not None and self._root != self.root))

    def finish(self, frame: Frame) -> Frame:
        local = self.bones
        if self.rotation_only():  # the avatar's bones, turned as the sender says
            rest = avatar()
            local = {name: (rest.get(name, p), q) for name, (p, q) in local.items()}
        frame.points = unity.world_positions(self.root, local)
        return frame

    def rotation_only(self) -> bool:
        """Every bone but the hips is at 0 0 0 in its parent (a sender of rotations
        alone; a real skeleton has some bones away from their parents)."""
        others = [p for name, (p, _) in self.bones.items() if name != "Hips"]
        return len(others) >= 3 and all(p == (0.0, 0.0, 0.0) for p in others)


Place = tuple[Num("model_xy"), Num("model_xy"), Num("model_xy")]


class AvatarSpec(Spec, kw_only=True):
    description: str = ""
    unit: Num("source_unit") = 1.0
    bones: Annotated[dict[str, Place], Meta(min_length=1)]


def parse_avatar(located) -> dict[str, unity.Vec]:
    """The rotation-only avatar file (``puppet check`` reads it too): Unity bone -> its
    place in its parent's frame at rest, metres."""
    spec = validate(located, AvatarSpec)
    for name in spec.bones:
        if name not in unity.PARENTS:
            import difflib

            close = difflib.get_close_matches(name, unity.BONES, n=1)
            raise located.error(("bones", name), f"'{name}' is not a Unity humanoid bone"
                                f"{'; did you mean ' + repr(close[0]) + '?' if close else ''}",
                                prefer_key=True)
    return {n: tuple(c * spec.unit for c in v) for n, v in spec.bones.items()}


@functools.lru_cache(maxsize=1)
def avatar() -> dict[str, unity.Vec]:
    """The shipped rotation-only avatar (``AVATAR``)."""
    from puppet.data.yamlfile import load_file

    return parse_avatar(load_file(AVATAR))


# -- encoding (what ``puppet mocap send`` writes) -----------------------------------------
def _message(address: str, *args) -> object:
    builder = OscMessageBuilder(address=address)
    for a in args:
        builder.add_arg(a, "s" if isinstance(a, str) else "i" if isinstance(a, int) else "f")
    return builder.build()


def encode_frame(time: float, bones: dict[str, tuple[unity.Vec, unity.Quat]],
                 root: tuple[unity.Vec, unity.Quat] = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
                 ) -> bytes:
    """One frame as one bundle: the root, every bone's local transform, the time and
    OK (floats are float32, as VMC senders write them)."""
    bundle = OscBundleBuilder(IMMEDIATELY)
    bundle.add_content(_message(ROOT, "root", *root[0], *root[1]))
    for name, (p, q) in bones.items():
        bundle.add_content(_message(BONE, name, *p, *q))
    bundle.add_content(_message(TIME, float(time)))
    bundle.add_content(_message(OK, 1))
    return bundle.build().dgram
