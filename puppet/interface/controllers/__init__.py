"""The interface runtime's controllers: each runs one kind of time-driven action.

The runtime (``puppet.interface.runtime``) is an arbiter: it decides which input or
key starts what, and who owns which joint. Each controller here runs one kind of
ongoing action and shares one protocol (``Controller``): ``tick`` does what is due at a
step, ``next_wakeup`` says when it is next due (None: idle), ``get_state``/``set_state``
carry it through snapshots as plain values, ``adopt`` takes over a running action from
the controller of the interface a hot reload replaces, and ``stop`` ends it. A
``tick`` that had nothing to do at that step (a sequence holding its pose, a
control-rate controller between its steps; a blend or sensor maps at every step that
only wrote targets) returns ``WAITED``, and the arbiter keeps its schedule; returning
None is always safe (the arbiter asks every controller again).
"""
