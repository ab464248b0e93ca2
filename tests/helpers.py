"""Shared helpers for tests: run a scripted performance through the real session."""

from __future__ import annotations

from dataclasses import dataclass, field

from puppet.data.catalog import find, load_setup
from puppet.session import Session
from puppet.timeline.playback import play
from puppet.timeline.script import compile_script, load_script, run_seconds


@dataclass
class Run:
    session: Session
    samples: list[dict] = field(default_factory=list)


def run_script(script: str, interface: str, scene: str | None = None, every: int = 4) -> Run:
    """Play a script headless, sampling sensors every ``every`` steps."""
    spec = load_script(find("script", script))
    session = Session(load_setup(interface, scene))
    run = Run(session)
    c = session.character

    def sample(s: Session) -> None:
        run.samples.append({
            "t": s.time,
            "base_x": c.bodies["base"].position.x,
            "base_bottom": min(sh.cache_bb().bottom for sh in c.shapes["base"]),
            "base_contact": c.in_contact("base"),
            "upright": c.upright(),
            "touching": any(c.in_contact(n) for n in c.link_order),
        })

    sample(session)
    until = round(run_seconds(spec) / session.sim.dt)
    play(session, compile_script(spec, session.sim.dt), until, every, sample)
    return run
