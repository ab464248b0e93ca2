"""A spec's ``mocap``: a clip that plays along every try, as ``puppet play --headless
--mocap CLIP [--mapping M] [--loop]`` plays it along a script. The search varies the
keys and the mouse; the performer's channels are the same in every try, merged with the
try's input the way the command merges them (by step, the script's events first at a
step), so a kept stage is what the recorded log does.

A stage owns the clip's samples from its checkpoint up to (not including) its end step,
its look-ahead the ones from there on; the start owns those before the first stage.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

Pairs = list[tuple[int, dict]]


class Performer:
    """The clip's (step, channels event) pairs, made once and extended as the search
    asks for later steps (a looping clip has no end)."""

    def __init__(self, mocap, setup, dt: float):
        from puppet.data.catalog import find
        from puppet.mocap.clip_source import ClipSource
        from puppet.mocap.clips import choose_mapping, open_clip

        self.clip_path = Path(find("clip", mocap.clip))  # the clip first: is it there?
        mapping, where, _ = choose_mapping(mocap.clip, mocap.mapping, setup.interface,
                                           setup.interface_path, setup.character)
        self.mapping, self.mapping_where = mapping, where
        self.source = ClipSource(open_clip(mocap.clip, mapping), name=self.clip_path.stem,
                                 loop=mocap.loop)
        self.dt = dt
        self.command = " ".join(["--mocap", mocap.clip]
                                + (["--mapping", mocap.mapping] if mocap.mapping else [])
                                + (["--loop"] if mocap.loop else []))
        self._pairs: Pairs = []
        self._seconds = -1.0

    def between(self, first: int, stop: int) -> Pairs:
        """The samples at steps ``first`` <= step < ``stop``."""
        seconds = stop * self.dt
        if seconds > self._seconds:  # ClipSource.events from 0: the command's very samples
            self._seconds = max(seconds, 2 * self._seconds, 10.0)
            self._pairs = self.source.events(self.dt, self._seconds)
        return [(s, e) for s, e in self._pairs if first <= s < stop]

    def fingerprint(self) -> bytes:
        """What the samples depend on besides the spec's words: the clip's and the
        mapping's bytes."""
        h = hashlib.sha1(self.clip_path.read_bytes())
        where = Path(self.mapping_where)
        if where.is_file():
            h.update(where.read_bytes())
        else:  # a rig recognised from the clip: the clip's bytes already say it
            h.update(self.mapping_where.encode())
        return h.digest()


def merged(script: Pairs, clip: Pairs) -> Pairs:
    """The script's pairs and the clip's in the order ``puppet play`` applies them: by
    step, the script's first at a step (a stable sort of script + clip)."""
    if not clip:
        return list(script)
    return sorted(list(script) + list(clip), key=lambda e: e[0])


__all__ = ["Performer", "merged"]
