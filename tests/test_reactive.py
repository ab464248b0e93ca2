"""Reactive scripts: rules that act a reaction delay after a condition becomes true.

A run of one records a log that replays to the same bits with no script; without noise
it is deterministic; with the human model's noise (a playtest's) its presses follow the
condition - a landing - not the clock; a state condition fires on entering the state;
the window plays the same rules; and a rule naming what the interface lacks is refused
at its line."""

from __future__ import annotations

import pytest

from puppet.data.catalog import load_setup
from puppet.data.errors import DataError
from puppet.data.playtest import noise_at
from puppet.data.yamlfile import load_text
from puppet.session import Session
from puppet.timeline.log import read_log
from puppet.timeline.reactive import ScriptPlayer, Speed, play_script
from puppet.timeline.replay import replay
from puppet.timeline.script import check_links, parse_script

DT = 1 / 480
AFTER = 0.3  # s of real time between a landing and the next hop's press
HOPS = f"""
description: Luxo hops again each time it lands - w {AFTER} s after the base touches down.
interface: luxo-keys
seconds: 6
events:
  - {{t: 0.5, key: w}}
rules:
  - {{when: {{sensor: contact.base, is: true}}, after: {AFTER}, key: w}}
"""


def _spec(text: str = HOPS):
    return parse_script(load_text(text, "hops.yaml"))


def _run(spec, noise=None, seed: int = 0, index: int = 0, seconds: float = 6.0):
    """(session, press steps, steps at which a control poll first saw the base down)."""
    setup = load_setup("luxo-keys")
    session = Session(setup)
    presses: list[int] = []
    session.listener = lambda step, e: presses.append(step) \
        if e["type"] == "key" and e["down"] else None
    landings: list[int] = []
    seen = {"down": None}

    def watch(s: Session) -> None:  # every control period, as the rule polls
        down = s.character.in_contact("base")
        if seen["down"] is False and down:
            landings.append(s.steps)
        seen["down"] = down if s.steps > 0 else None

    speed = Speed(1.0)
    player = ScriptPlayer(session, spec, round(seconds / DT), speed, speed.apply, noise,
                          seed, index)
    play_script(session, player, 8, watch)
    return session, presses, landings


def test_a_reactive_run_replays_to_the_same_bits_with_no_script(tmp_path):
    from puppet.app.headless import run_headless
    from puppet.timeline.script import compile_script

    spec = _spec()
    path = tmp_path / "hops.jsonl"
    session = run_headless(load_setup("luxo-keys"), compile_script(spec, DT), 6.0,
                           record=path, rules=spec, script=("hops", HOPS))
    log = read_log(path)
    assert log.header["script"] == "hops" and "contact.base" in log.header["script_text"]
    presses = [e.step for e in log.events if e.event["type"] == "key" and e.event["down"]]
    assert len(presses) >= 4  # the timed hop, then a hop after each landing
    result = replay(path, check=False)
    assert result.same_end and result.final_hash == session.sim.state_hash()
    again, _, _ = _run(spec)  # the same run from the player alone: the same bits
    assert again.sim.state_hash() == session.sim.state_hash()


def test_without_noise_a_reactive_script_is_deterministic_and_reacts_after_its_delay():
    a, presses, landings = _run(_spec())
    b, presses_b, _ = _run(_spec())
    assert a.sim.state_hash() == b.sim.state_hash() and presses == presses_b
    assert presses[0] == 240  # the timed press at 0.5 s
    for p in presses[1:]:  # each later press 0.3 s after a landing the rule saw
        assert any(p - land == round(AFTER / DT) for land in landings), (p, landings)


def test_with_noise_the_presses_follow_the_condition_not_the_clock():
    spec = _spec()
    _, clock, _ = _run(spec)  # the script as written: where a clock would press
    human = noise_at("human")
    low = round((AFTER - human.timing_ms / 1000) / DT) - 1
    high = round((AFTER + human.timing_ms / 1000) / DT) + 1
    drift = []
    for index in range(3):
        _, presses, landings = _run(spec, human, seed=3, index=index)
        assert len(presses) >= 4
        for p in presses[1:]:
            delays = [p - land for land in landings if land <= p]
            # a landing's bounce (the base touching again within the delay) is a later
            # landing the rule already saw: the press follows one of them
            assert any(low <= d <= high for d in delays), (index, p, landings)
        drift.append(max(abs(p - c) for p, c in zip(presses[1:], clock[1:])))
    # the landings moved (each hop started elsewhere) and the presses went with them,
    # further than a clock's presses moved by the same error could go
    assert max(drift) > high - round(AFTER / DT), drift


def test_a_state_condition_fires_when_the_state_is_entered():
    spec = _spec("""
interface: luxo-keys
events:
  - {t: 0.5, key: z}
rules:
  - {when: {state: sitting}, after: 1.0, key: v}
""")
    session, presses, _ = _run(spec, seconds=4.0)
    assert presses[0] == 240
    # entered at the press (step 240, after that step's poll); seen at the next control
    # step (248, the control period is 8 steps); 1.0 s later: v
    assert presses[1] == 248 + round(1.0 / DT)
    assert len(presses) == 2  # it fires once: the state is not entered again


@pytest.mark.parametrize("when, words", [
    ("{sensor: contact.lamp, is: true}", "unknown link 'lamp'"),
    ("{sensor: angle.base, is: true}", "'is' only applies to contact"),
    ("{state: flying}", "no state 'flying'"),
    ("{mode: dancing}", "no mode 'dancing'"),
    ("{sensor: lean, above: 10, state: sitting}", "exactly one of sensor"),
    ("[{state: [upright, flying]}, {sensor: contact.base, is: true}]", "no state 'flying'"),
])
def test_a_rule_naming_what_the_interface_lacks_is_refused_at_its_line(tmp_path, when, words):
    message = refusal(tmp_path, "luxo-keys", when)
    assert words in message and "bad.yaml:3:" in message, message


def refusal(tmp_path, interface: str, when: str) -> str:
    """The DataError a one-rule script on ``interface`` gets at load (its rule on line
    3: ``when``), as ``puppet play --input`` checks it."""
    text = f"interface: {interface}\nrules:\n  - {{when: {when}, after: 0.2, key: w}}\n"
    path = tmp_path / "bad.yaml"
    path.write_text(text, encoding="utf-8")
    setup = load_setup(interface)
    with pytest.raises(DataError) as caught:
        spec = parse_script(load_text(text, str(path)))
        check_links(path, spec, [link.name for link in setup.character.links],
                    setup.interface, setup.character)
    return str(caught.value)


def test_the_window_plays_the_rules_on_its_clock(tmp_path, monkeypatch):
    import pygame

    from puppet.app import window

    frames = {"n": 0}
    real_get = pygame.event.get

    def fake_get(*args, **kw):
        real_get()
        frames["n"] += 1
        return [pygame.event.Event(pygame.QUIT)] if frames["n"] >= 240 else []

    monkeypatch.setattr(pygame.event, "get", fake_get)
    monkeypatch.setattr(pygame.mouse, "get_focused", lambda: False)
    path = tmp_path / "window.jsonl"
    setup = load_setup("luxo-keys")
    assert window.run_window(setup, 1.0, record=str(path), script=_spec(),
                             script_text=("hops", HOPS)) == 0
    log = read_log(path)
    presses = [e.step for e in log.events if e.event["type"] == "key" and e.event["down"]]
    assert log.header["script"] == "hops" and presses and presses[0] == 240
    result = replay(path, check=False)
    assert result.same_end  # what the rules did is in the log
    if log.last_step > 240 + 600:  # the run lasted past a hop and its reaction
        assert len(presses) >= 2
        _, expected, _ = _run(_spec(), seconds=log.last_step * DT)
        assert presses == [p for p in expected if p <= log.last_step][:len(presses)]


def test_a_list_of_conditions_must_all_hold_and_for_waits_until_they_have_held():
    spec = _spec("""
interface: luxo-keys
events:
  - {t: 0.5, key: w}
rules:
  - when: [{state: [upright, sitting]}, {sensor: contact.base, is: true}]
    for: 0.1
    after: 0.2
    key: w
""")
    _, presses, landings = _run(spec)
    assert len(presses) >= 3
    for p in presses[1:]:  # held 0.1 s (48 steps: six polls), then 0.2 s (96 steps)
        assert any(p - land == 48 + 96 for land in landings), (p, landings)
