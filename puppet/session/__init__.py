"""The Session and what it keeps of its own past.

``session.py``: the Session, one interface on one character in one scene, the only code
path from input events to physics; ``history.py``: its checkpoints and rewind (and the
scrubber that moves through them); ``preview.py``: the scrub's cached poses;
``playback.py``: feeding timed events into a session (the one stepping rule every
replay follows). They sit in one package because the Session replays its own history
through ``playback`` and rebuilds its past with ``history``: the timeline (logs,
scripts, replay, expectations) is built on top of them.
"""

from puppet.session.session import Session, world_box

__all__ = ["Session", "world_box"]
