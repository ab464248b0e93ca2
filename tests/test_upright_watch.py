"""A headless play's ``upright=`` is over the last second, not the last step (issue 31):
a search that keeps tries by it must not keep a lamp caught mid-somersault."""

from __future__ import annotations

from types import SimpleNamespace

from puppet.commands import main
from puppet.physics.upright_watch import UprightWatch


def _play(capsys, seconds: str) -> str:
    assert main(["play", "luxo-keys", "--headless", "--input", "luxo-keys-somersaults",
                 "--seconds", seconds]) == 0
    return capsys.readouterr().out.strip().splitlines()[-1]


def test_a_lamp_mid_somersault_is_not_upright_though_its_base_is_level_now(capsys):
    # at 1.6 s the base has just landed, 24 deg from level (within the 45 of
    # Character.upright), 0.4 s after upside down (175 deg at 1.20 s); settled by 3 s
    mid = _play(capsys, "1.6")
    assert "upright=False (root 175 deg from upright at t=1.20s)" in mid, mid
    assert mid.startswith("t=1.600s") and mid.endswith("state=75c957a27575f865")
    assert "upright=True  state=" in _play(capsys, "3.0")


def test_the_watch_keeps_the_last_second_and_forgets_a_rewound_future():
    def at(t, angle):
        return SimpleNamespace(time=t, character=SimpleNamespace(root_angle=lambda: angle))

    watch = UprightWatch()
    for k in range(121):  # 2 s at 60 Hz: tipped over (90 deg) in the first second only
        watch(at(k / 60, 1.5708 if k < 60 else 0.0))
    assert watch.stayed(at(2.0, 0.0))
    assert not watch.stayed(at(1.5, 0.0))  # back to 1.5 s: the tipped samples count again
    assert watch.worst(at(1.5, 0.0))[1] < 1.0
    watch = UprightWatch()
    watch(at(0.0, 6.2832))  # a full turn is upright; a short run is watched whole
    assert watch.said(at(0.1, 3.0)) == "upright=False (root 172 deg from upright at t=0.10s)"
