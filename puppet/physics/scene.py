"""Build a scene's static ground (polylines with per-segment friction) into a space."""

from __future__ import annotations

import pymunk

from puppet.data.scenes import SceneSpec


def build_ground(spec: SceneSpec, space: pymunk.Space) -> list[pymunk.Segment]:
    segments = []
    for ground in spec.ground:
        for a, b in zip(ground.points, ground.points[1:]):
            seg = pymunk.Segment(space.static_body, a, b, ground.thickness / 2)
            seg.friction = ground.friction
            seg.elasticity = ground.elasticity
            segments.append(seg)
    space.add(*segments)
    return segments
