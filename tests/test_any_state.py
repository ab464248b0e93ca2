"""``any_state`` transitions: a key or condition that works in every state of a
machine, without re-entering the state it leads to, and ``goto`` loops that stop."""

from __future__ import annotations

from helpers import session_of

from puppet.interface import events as ev


def test_an_any_state_transition_does_not_re_enter_the_state_it_leads_to(tmp_path):
    s = session_of(tmp_path, """
    name: t
    description: two machines with a state of the same name
    character: luxo
    keys:
      - {key: j, goto: watch.busy}
    initial: idle
    states:
      idle: {}
    machines:
      watch:
        initial: idle
        states:
          idle: {}
          busy: {}
        any_state:
          transitions:
            - {to: idle, after: 0.1}
    """)
    watch = s.runtime.machines["watch"]
    s.advance(480)
    assert (watch.current, watch.entered) == ("idle", 0)  # in idle: nothing to do
    s.handle(ev.key("j", True))
    assert watch.current == "busy"
    s.advance(60)  # 0.125 s: any_state takes it back to idle once
    assert watch.current == "idle" and 480 < watch.entered <= 540
    entered = watch.entered
    s.advance(240)
    assert watch.entered == entered


def test_an_any_state_key_works_in_every_state_and_gotos_that_loop_stop(tmp_path):
    s = session_of(tmp_path, """
    name: t
    description: an any_state key; two states that go to each other on entry
    character: luxo
    keys:
      - {key: l, goto: ping}
    initial: rest
    states:
      rest: {}
      ping: {enter: {goto: pong}}
      pong: {enter: {goto: ping}}
      other: {}
    any_state:
      keys:
        - {key: t, goto: rest}
        - {key: o, goto: other}
    """)
    main = s.runtime.machines["main"]
    for key, state in (("o", "other"), ("t", "rest"), ("o", "other"), ("o", "other")):
        s.handle(ev.key(key, True))
        s.handle(ev.key(key, False))
        assert main.current == state, key
    s.handle(ev.key("l", True))  # ping -> pong -> ping ...: stopped after a few, no hang
    s.handle(ev.key("l", False))
    assert main.current in ("ping", "pong")
    s.advance(10)
