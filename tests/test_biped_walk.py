"""The walk feat (assets/logs/biped-walk): the human figure walks 10 m and more on the
mouse and the swap key. Its expectations must fail when the physics under it breaks."""

from __future__ import annotations

import json
from pathlib import Path

import yaml

from puppet.data.catalog import ROOT, find
from puppet.testing import replay_log
from test_luxo_feats import _failed, _weakened

LOG = ROOT / "assets" / "logs" / "biped-walk.jsonl"


def test_the_walk_log_meets_its_expectations():
    result = replay_log(str(LOG))
    assert not result.failed, [str(o) for o in result.outcomes]


def test_the_walk_log_fails_with_weak_hips(tmp_path):
    spec = yaml.safe_load(find("interface", "biped-walk").read_text(encoding="utf-8"))
    spec["gains"] = {j: {"stiffness": 300.0, "max_torque": 75.0}
                     for j in ("hip_near", "hip_far")}
    spec["name"] = "biped-walk-weak"
    iface = tmp_path / "biped-walk-weak.yaml"
    iface.write_text(yaml.safe_dump(spec), encoding="utf-8")
    lines = LOG.read_text(encoding="utf-8").splitlines(keepends=True)
    head = json.loads(lines[0])
    head.update(interface=str(iface), interface_text=iface.read_text(encoding="utf-8"))
    out = tmp_path / LOG.name
    out.write_text(json.dumps(head) + "\n" + "".join(lines[1:]), encoding="utf-8")
    side = LOG.parent / "biped-walk.expect.yaml"
    (tmp_path / side.name).write_text(side.read_text(encoding="utf-8"), encoding="utf-8")
    assert {"never_fell", "x_at_end"} <= _failed(out)


def test_the_walk_log_fails_on_a_slippery_track(tmp_path):
    assert {"never_fell", "x_at_end"} <= _failed(_weakened("biped-walk", Path(tmp_path), friction=0.3))
