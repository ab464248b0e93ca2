"""Which key, button or stick press is bound to what: the one place key ownership is
decided.

A chord belongs, in this order, to the interface (each state machine's current state's
keys, then its ``any_state`` keys, then the top level's), to a recorded gesture bound to
it, to the app (its action as the interface's ``app_keys`` leave it), or to nobody. The
runtime resolves a press once (``resolve``); the session and the window ask the
runtime (``InterfaceRuntime.resolve``, ``Session.app_action_of``), never the tables.
"""

from __future__ import annotations

from typing import NamedTuple

from puppet.data.actions import ActionSpec
from puppet.data.interfaces import InterfaceSpec
from puppet.data.keys import normalize_key
from puppet.interface.app_keys import AppAction


class Resolved(NamedTuple):
    """Who a chord belongs to now: an interface action (and the state machine it
    belongs to, None for the top level's keys), a gesture, the app, or nobody."""

    action: ActionSpec | None = None
    machine: str | None = None
    gesture: bool = False
    app: AppAction | None = None

    @property
    def interface(self) -> bool:
        """The interface's input (an action or a gesture), not the app's."""
        return self.action is not None or self.gesture


NOBODY = Resolved()


class KeyBindings:
    """An interface's key tables, built once per runtime (``scene``: keys for other
    scenes are not bound)."""

    def __init__(self, spec: InterfaceSpec, scene: str | None):
        machines = spec.state_machines()
        self.top = {normalize_key(k.key): k for k in spec.keys if k.plays_on(scene)}
        # (machine, state) -> chord -> action; machine -> chord -> action (any_state)
        self.state = {(mname, sname): {normalize_key(k.key): k for k in s.keys
                                       if k.plays_on(scene)}
                      for mname, m in machines.items()
                      for sname, s in m.states.items()}
        self.any = {mname: {normalize_key(k.key): k for k in m.any_state.keys
                            if k.plays_on(scene)}
                    for mname, m in machines.items()}
        self.app = {key: AppAction(action) for action, key in spec.app_key_table().items()}

    def lookup(self, chord: str, machines: dict) -> tuple[ActionSpec | None, str | None]:
        """The interface action bound to a chord now and the machine it belongs to."""
        for name, machine in machines.items():
            found = self.state[(name, machine.current)].get(chord)
            if found is None:
                found = self.any[name].get(chord)
            if found is not None:
                return found, name
        return self.top.get(chord), None

    def resolve(self, chord: str, machines: dict, gestures) -> Resolved:
        """Who owns ``chord`` now (``gestures``: the chords recorded gestures play on).
        An interface that binds an app's key must have moved the app's action
        elsewhere (the loader refuses it otherwise), so the interface comes first."""
        action, machine = self.lookup(chord, machines)
        if action is not None:
            return Resolved(action, machine)
        if chord in gestures:
            return Resolved(gesture=True)
        app = self.app.get(chord)
        return NOBODY if app is None else Resolved(app=app)
