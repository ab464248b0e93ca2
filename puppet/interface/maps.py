"""Continuous maps: pure functions from an input value to a joint target (radians)."""

from __future__ import annotations

import math

from puppet.data.interfaces import LinearMapSpec


def linear(spec: LinearMapSpec, value: float) -> float:
    """Target (radians) for an input value: linear from ``from`` onto ``to``, clamped."""
    (x0, x1), (y0, y1) = spec.from_, spec.to
    u = (value - x0) / (x1 - x0)
    if spec.clamp:
        u = min(1.0, max(0.0, u))
    return math.radians(y0 + u * (y1 - y0))
