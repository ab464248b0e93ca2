"""A character's own PD gains act only where an interface leaves them out; every gain
that acts in a shipped layout is guarded by a shipped log: change it and that log no
longer replays to its recorded state."""

import json
from pathlib import Path

import pytest

from puppet.data import catalog
from puppet.data.catalog import load_setup
from puppet.timeline.replay import replay

ROOT = Path(__file__).resolve().parents[1]
COMPONENTS = ("stiffness", "damping", "max_torque")


def acting_gains() -> dict[tuple[str, str, str], set[str]]:
    """(character, joint, component) -> the shipped interfaces that use the
    character's own value (they do not set it in ``gains``)."""
    out: dict = {}
    for path in sorted((ROOT / "interfaces").glob("*.yaml")):
        setup = load_setup(str(path))
        for joint in setup.character.actuated:
            own = setup.interface.gains.get(joint.name)
            for comp in COMPONENTS:
                if own is None or getattr(own, comp) is None:
                    out.setdefault((setup.character.name, joint.name, comp), set()).add(
                        path.stem)
    return out


def logs_by_interface() -> dict[str, list[Path]]:
    out: dict = {}
    for log in sorted((ROOT / "assets" / "logs").glob("*.jsonl")):
        header = json.loads(log.read_text(encoding="utf-8").splitlines()[0])
        out.setdefault(header["interface"], []).append(log)
    return out


def test_luxo_runs_on_its_own_gains_only_in_luxo_designer():
    """What characters/luxo.yaml and docs/interfaces.md say."""
    luxo = {k: v for k, v in acting_gains().items() if k[0] == "luxo"}
    assert luxo == {("luxo", "ankle", c): {"luxo-designer"} for c in COMPONENTS}


def _replay_hash(log: Path, until: int | None, monkeypatch, change=None) -> str:
    real = catalog.parse_character

    def changed(located):
        spec = real(located)
        if change is not None and spec.name == change[0]:
            pd = spec.joint(change[1]).pd
            setattr(pd, change[2], getattr(pd, change[2]) * change[3])
        return spec

    with monkeypatch.context() as m:
        m.setattr(catalog, "parse_character", changed)
        return replay(log, until_step=until, check=False, trajectory=False).final_hash


@pytest.mark.parametrize("character", ["luxo", "cat"])
def test_every_acting_character_gain_is_guarded_by_a_log(character, monkeypatch):
    """Stiffness and damping: 2 % more changes the state of a log that plays it within
    1.5 s. A torque limit acts only when a servo saturates: half of it changes a whole
    log's end (a limit no log reaches would not be acting)."""
    by_iface = logs_by_interface()
    plain: dict = {}
    for gain, interfaces in sorted(acting_gains().items()):
        if gain[0] != character:
            continue
        logs = [log for iface in sorted(interfaces) for log in by_iface.get(iface, [])]
        assert logs, f"no shipped log plays an interface using {'.'.join(gain)} of its own"
        if gain[2] == "max_torque":
            changed = any(_replay_hash(log, None, monkeypatch, gain + (0.5,))
                          != json.loads(log.read_text().splitlines()[-1])["hash"]
                          for log in logs)
            assert changed, f"halving {'.'.join(gain)} changes none of {logs}"
        else:
            log = logs[0]
            if log not in plain:
                plain[log] = _replay_hash(log, 720, monkeypatch)
            assert _replay_hash(log, 720, monkeypatch, gain + (1.02,)) != plain[log], gain
