"""The app's actions as a runtime vocabulary: what a key asks of the app.

The keys themselves (``APP_KEYS``, which key runs which action by default) and the key
names data files are checked against are data, in ``puppet.data.keys``; here are the
typed values the interface runtime, the session and the window pass around.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from puppet.data.keys import APP_KEYS


class _Named(str, Enum):
    def __str__(self) -> str:
        return self.value

    __format__ = str.__format__


# The app's actions as a typed vocabulary, one member per entry of APP_KEYS (a ``str``
# so that it prints, logs and compares as its name): what a key asks of the app, or an
# interface's ``app:``. AppAction.PAUSE == "pause".
AppAction = _Named("AppAction", {name.upper(): name for name in APP_KEYS})


@dataclass(frozen=True)
class SetSlowdown:
    """Set the slowdown to ``value`` (an interface key's ``slowdown:``)."""

    value: float


# Actions that change the simulation (and so are handled by the Session, replayed
# from logs); the others only change how the window presents it.
SIM_ACTIONS = frozenset({AppAction.RESET, AppAction.CHECKPOINT, AppAction.RESTORE})
