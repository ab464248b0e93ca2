"""Every body's position, angle, velocity and spin in one C call.

The control layer reads the figure at each control step (the centre of mass and its
velocity, links' places, KD tracking's pulls). Asking pymunk body by body costs a
call per value; pymunk's batch API (``pymunk.batch``) hands every body of a space
over at once, through the iterator pymunk ships for it, into one float array:
``x, y, angle, vx, vy, spin`` per body, ``x, y`` being what ``Body.position`` gives.
A space keeps its bodies in one order until one is added or removed, or it is re-seated
(a restore builds a new space, or re-seats the live one in place - in the order a new
space gets, which need not be the one it had: the space's own static body comes last
there, first when the scene was built), so where each body's row is is worked out once
per space and seat (``space._puppet_seat``, counted by ``puppet.physics.reseat``).

The values are the very floats the per-body calls return; what a caller works out
from them must be done with the same arithmetic as Chipmunk (``to_world``), so that
a figure read this way moves to the same bits as one read body by body.
"""

from __future__ import annotations

import math

from pymunk._chipmunk_cffi import ffi, lib

FIELDS = 2 | 4 | 8 | 16  # pymunk.batch.BodyFields: POSITION | ANGLE | VELOCITY | ANGULAR_VELOCITY
WIDTH = 6  # floats per body: x, y, angle, vx, vy, spin
_BODY_ID = 1  # pymunk.batch.BodyFields.BODY_ID (the body's pointer, = Body.id)
_EACH = lib.cpSpaceEachBody
_GET = ffi.addressof(lib, "pmSpaceBodyGetIteratorFuncBatched")
_UNPACK = ffi.unpack


class BodyReader:
    """Reads a space's bodies in bulk; ``offsets(bodies)`` says where each one's six
    values start in what ``read`` returns."""

    def __init__(self):
        self._floats = lib.pmFloatArrayNew(0)
        self._ints = lib.pmIntArrayNew(0)
        self._data = ffi.new("pmBatchedData *")
        self._data.floatArray = self._floats
        self._data.intArray = self._ints
        self._space = None  # the space the offsets were worked out for, and its seat
        self._seat = 0
        self._offsets: dict[int, int] = {}

    def read(self, space) -> list[float]:
        """``[x, y, angle, vx, vy, spin, ...]`` of every body of ``space``, in its order."""
        if space is not self._space or space.__dict__.get("_puppet_seat", 0) != self._seat:
            self._index(space)
        floats = self._floats
        floats.num = 0
        _EACH(space._space, _GET, self._data)
        return _UNPACK(floats.arr, floats.num)

    def offset(self, space, body) -> int:
        """Where ``body``'s values start in ``read(space)``."""
        if space is not self._space or space.__dict__.get("_puppet_seat", 0) != self._seat:
            self._index(space)
        return self._offsets[body.id]

    def _index(self, space) -> None:
        data, floats, ints = self._data, self._floats, self._ints
        floats.num = ints.num = 0
        data.fields = FIELDS | _BODY_ID
        try:
            _EACH(space._space, _GET, data)
        finally:
            data.fields = FIELDS
        ids = _UNPACK(ints.arr, ints.num)
        self._offsets = {body_id: WIDTH * i for i, body_id in enumerate(ids)}
        self._space = space
        self._seat = space.__dict__.get("_puppet_seat", 0)

    def __del__(self):
        try:
            lib.pmFloatArrayFree(self._floats)
            lib.pmIntArrayFree(self._ints)
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass


def to_world(x: float, y: float, angle: float, px: float, py: float) -> tuple[float, float]:
    """A body's local point (px, py) in the world, from its ``position`` (x, y) and
    ``angle``: Chipmunk's ``cpBodyLocalToWorld`` to the bit (its transform is
    ``[cos -sin x'; sin cos y']`` with the rotation ``cpvforangle(angle)``, and the
    position it gives back is that transform's translation)."""
    c, s = math.cos(angle), math.sin(angle)
    return (c * px + -s * py + x, s * px + c * py + y)
