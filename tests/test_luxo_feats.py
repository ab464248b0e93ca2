"""Luxo's mouse feats (issue 15): each log fails named expectations when the interface
or the physics is weakened, and the expectations they use measure what they say."""

from __future__ import annotations

import json
import shutil
from functools import lru_cache
from pathlib import Path

import pytest
import yaml

from puppet.data.catalog import ROOT, find
from puppet.testing import check, replay_log

LOGS = ROOT / "assets" / "logs"


@lru_cache(maxsize=None)
def replayed(name: str):
    return replay_log(str(LOGS / f"{name}.jsonl"))


def _weakened(name: str, tmp_path: Path, *, servos: float = 1.0, friction: float = 1.0,
              gravity: float = 1.0) -> Path:
    """A copy of the log (and its sidecar) replaying against a weakened copy of its
    interface (servo stiffness and torque times ``servos``) and scene (friction and
    gravity times the factors)."""
    log = LOGS / f"{name}.jsonl"
    lines = log.read_text(encoding="utf-8").splitlines(keepends=True)
    head = json.loads(lines[0])
    iface = yaml.safe_load(find("interface", head["interface"]).read_text(encoding="utf-8"))
    for gains in iface.get("gains", {}).values():
        gains["stiffness"] *= servos
        gains["max_torque"] *= servos
    iface["name"] += "-weak"
    scene = yaml.safe_load(find("scene", head["scene"]).read_text(encoding="utf-8"))
    for g in scene["ground"]:
        g["friction"] = g.get("friction", 0.8) * friction
    scene["gravity"] = [v * gravity for v in scene.get("gravity", [0.0, -9.81])]
    scene["name"] += "-weak"
    iface["scene"] = str(tmp_path / "scene-weak.yaml")
    (tmp_path / "scene-weak.yaml").write_text(yaml.safe_dump(scene), encoding="utf-8")
    ipath = tmp_path / "iface-weak.yaml"
    ipath.write_text(yaml.safe_dump(iface), encoding="utf-8")
    head.update(interface=str(ipath), interface_text=ipath.read_text(encoding="utf-8"),
                scene=str(tmp_path / "scene-weak.yaml"))
    out = tmp_path / log.name
    out.write_text(json.dumps(head) + "\n" + "".join(lines[1:]), encoding="utf-8")
    shutil.copy(LOGS / f"{name}.expect.yaml", tmp_path / f"{name}.expect.yaml")
    return out


def _failed(path: Path) -> set[str]:
    result = replay_log(path)
    return {o.expectation.split()[0].rstrip(":") for o in result.failed} - {"same"}


# -- shuffle --------------------------------------------------------------------------
def test_shuffle_moves_half_a_metre_without_hopping():
    result = replayed("luxo-shuffle")
    assert not result.failed, [str(o) for o in result.failed]
    # a hop would fail the shuffle's airborne limit; the shuffle fails a hop's flight
    assert check(replayed("luxo-hop"), [{"airborne": {"link": "base", "max_seconds": 0.1}}])
    assert check(result, [{"airborne": {"link": "base", "min_seconds": 0.1}}])
    assert check(result, [{"airborne": {"link": "base", "max_seconds": 0.05}}])


def test_shuffle_fails_on_a_slippery_floor(tmp_path):
    assert "x_at_end" in _failed(_weakened("luxo-shuffle", tmp_path, friction=0.3))
