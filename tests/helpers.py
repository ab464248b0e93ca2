"""Shared helpers for tests: run a scripted performance through the real session."""

from __future__ import annotations

import json
import shutil
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from puppet.data.catalog import ROOT, find, load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.script import compile_script, load_script, run_seconds


def session_of(tmp_path: Path, text: str, name: str = "iface.yaml") -> Session:
    """A Session of the interface ``text`` (dedented), written to ``tmp_path / name``."""
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return Session(load_setup(str(path)))


def play_events(session: Session, events, until_step: int, chunk: int | None = None) -> None:
    """``events`` ((step, event) pairs in order) handled at their steps, the session
    advanced to each next one (in calls of at most ``chunk`` steps: runs cut between
    them), then to ``until_step``."""
    i = 0
    while session.steps < until_step:
        while i < len(events) and events[i][0] <= session.steps:
            session.handle(events[i][1])
            i += 1
        nxt = events[i][0] if i < len(events) else until_step
        to = min(nxt, until_step) if chunk is None else min(nxt, until_step,
                                                            session.steps + chunk)
        session.advance(max(1, to - session.steps))


def tap(session: Session, key: str) -> None:
    """Press and release ``key``."""
    session.handle(ev.key(key, True))
    session.handle(ev.key(key, False))


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


def copy_log(log: Path, dest: Path, **header) -> Path:
    """A copy of a log (and its sidecar) with header fields replaced."""
    lines = log.read_text(encoding="utf-8").splitlines(keepends=True)
    head = json.loads(lines[0])
    head.update(header)
    out = dest / log.name
    out.write_text(json.dumps(head) + "\n" + "".join(lines[1:]), encoding="utf-8")
    side = log.parent / (log.stem + ".expect.yaml")
    shutil.copy(side, dest / side.name)
    return out


def with_changed_interface(log: Path, interface: str, dest: Path, change,
                           suffix: str = "changed") -> Path:
    """A copy of ``log`` (and its sidecar) replaying against a copy of ``interface``
    edited in place by ``change(spec)`` (its YAML as plain data)."""
    spec = yaml.safe_load(find("interface", interface).read_text(encoding="utf-8"))
    change(spec)
    iface = dest / f"{interface}-{suffix}.yaml"
    iface.write_text(yaml.safe_dump(spec), encoding="utf-8")
    return copy_log(log, dest, interface=str(iface),
                    interface_text=iface.read_text(encoding="utf-8"))


def with_weak_hips(log_name: str, interface: str, dest: Path, stiffness: float,
                   max_torque: float) -> Path:
    """A copy of assets/logs/LOG_NAME (and its sidecar) replaying against a copy of
    ``interface`` whose hip servos have these gains (its other gains kept)."""
    def weaken(spec: dict) -> None:
        spec.setdefault("gains", {}).update(
            {j: {"stiffness": stiffness, "max_torque": max_torque}
             for j in ("hip_near", "hip_far")})
        spec["name"] = f"{interface}-weak"

    return with_changed_interface(ROOT / "assets" / "logs" / f"{log_name}.jsonl", interface,
                                  dest, weaken, suffix="weak")


# A two-joint BVH file: a root with six channels and one joint with three, two frames.
TWO_JOINT_BVH = """\
HIERARCHY
ROOT body
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT arm
  {
    OFFSET 0 1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 1 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.1
0 0 0 0 0 0 0 0 0
0 0 0 0 0 0 10 0 0
"""


class ListenedPort:
    """The port a command's live source listens on, when it is given port 0 (the
    system picks a free one at the bind, so no other test can take a probed number
    in between): ``wait()`` returns it once the source has started."""

    def __init__(self, monkeypatch):
        import threading

        from puppet.mocap.source import OscSource

        self.port: int | None = None
        self._ready = threading.Event()
        start = OscSource.start

        def started(source):
            out = start(source)
            self.port = source.port
            self._ready.set()
            return out
        monkeypatch.setattr(OscSource, "start", started)

    def wait(self, timeout: float = 10.0) -> int:
        assert self._ready.wait(timeout), "the live source never started"
        return self.port


ANKLE_IFACE = """
name: t
description: the ankle on the mouse
character: luxo
maps:
  - {input: mouse.x, joint: ankle, from: [0, 1], to: [60, -60]}
"""


def recorded_then_edited(tmp_path: Path) -> tuple[Path, Path]:
    """(interface, log): a second of the ankle on the mouse recorded in ``tmp_path``,
    then the interface file edited (its map's slope) after the recording."""
    from puppet.timeline.log import record_events

    iface = tmp_path / "t.yaml"
    iface.write_text(textwrap.dedent(ANKLE_IFACE))
    log = tmp_path / "t.jsonl"
    s = Session(load_setup(str(iface)))
    record_events(s, [(0, ev.mouse(1.0, 0.5)), (240, ev.mouse(0.0, 0.5))], 480, log)
    iface.write_text(textwrap.dedent(ANKLE_IFACE).replace("to: [60, -60]", "to: [10, -10]"))
    return iface, log


def swing_joints(sim, steps: int) -> None:
    """Swing every joint of ``sim``'s character for ``steps`` steps, 24 at a time, the
    targets a function of the time only (so two runs are comparable bit for bit): the
    checkpoint and re-seat tests' busy motion."""
    import math

    start = sim.character.start_joint_angles()
    for _ in range(0, steps, 24):
        for i, (name, servo) in enumerate(sim.character.servos.items()):
            servo.target = start.get(name, 0.0) + 0.6 * math.sin(3.0 * sim.time + i)
        sim.step(24)
