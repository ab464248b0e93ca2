"""``puppet check CHARACTER`` says whether the body stands with its targets held, and
why not: every shipped character stands (quietly and nudged); deliberately bad bodies
are told what is wrong with them (too soft, too weak, oscillating, locked by damping)."""

from __future__ import annotations

import math
import re

import pytest

from puppet.commands import main
from puppet.data.catalog import ROOT
from puppet.data.characters import load_character
from puppet.physics.stability import stability
from puppet.physics.stability_report import report

LUXO = (ROOT / "characters" / "luxo.yaml").read_text(encoding="utf-8")
ANKLE = "pd: {stiffness: 18.0, damping: 0.3, max_torque: 14.0}"
KNEE = "pd: {stiffness: 12.0, damping: 0.18, max_torque: 9.0}"


def lamp(tmp_path, name, ankle=ANKLE, knee=KNEE):
    """Luxo with other gains: a body whose trouble is known."""
    assert ANKLE in LUXO and KNEE in LUXO
    path = tmp_path / "characters" / f"{name}.yaml"
    path.parent.mkdir(exist_ok=True)
    path.write_text(LUXO.replace(ANKLE, ankle).replace(KNEE, knee), encoding="utf-8")
    return path


def check(capsys, *argv):
    code = main(["check", *map(str, argv)])
    out, err = capsys.readouterr()
    assert code == 0 and "Traceback" not in err
    return out, err


@pytest.mark.parametrize("name", ["luxo", "cat", "biped", "biped-small"])
def test_every_shipped_character_stands_held_and_nudged(name):
    s = stability(load_character(ROOT / "characters" / f"{name}.yaml"))
    assert s.stands and s.nudged.fell_at is None, (s.quiet, s.nudged)
    assert not s.oscillating and s.touching
    lines, warnings = report(s)
    assert lines[0].startswith("stands: held its start pose 5 s")
    assert all("falls" not in w and "oscillates" not in w for w in warnings)


def test_the_biped_ankles_are_reported_locked_as_the_notes_measure_them():
    """The ankle's 30 N*m*s/rad against a 0.006 kg*m^2 foot: e^-12 a step (docs/figures.md), and
    ankle damping 8 or less tracks (the guide): the report says both."""
    s = stability(load_character(ROOT / "characters" / "biped.yaml"))
    locked = {j.name: j for j in s.locked}
    assert set(locked) == {"ankle_near", "ankle_far"}
    ankle = locked["ankle_near"]
    assert ankle.light == "foot_near" and 11 < ankle.lam < 12.5
    assert 7 < ankle.track_damping < 8.5 and ankle.follow > 100
    loads = {tuple(x.joints): x for x in s.loads}
    ankles = loads[("ankle_near", "ankle_far")]  # the notes: "about m*g*h = 640 N*m/rad"
    assert 600 < ankles.topple < 680 and ankles.stiffness == 1600


def test_check_prints_the_report_after_the_ok_line_and_can_skip_it(capsys):
    out, err = check(capsys, "characters/luxo.yaml")
    assert out.splitlines()[0] == "characters/luxo.yaml: ok (character)"
    assert out.splitlines()[1].startswith("  stands: held its start pose 5 s (simulated)")
    assert "nudged" in out and err == ""
    out, err = check(capsys, "--no-stability", "characters/luxo.yaml")
    assert out == "characters/luxo.yaml: ok (character)\n" and err == ""


def test_a_soft_ankle_falls_and_is_told_its_stiffness_against_m_g_h(tmp_path, capsys):
    path = lamp(tmp_path, "soft", ankle="pd: {stiffness: 1.0, damping: 0.02, max_torque: 14.0}")
    out, err = check(capsys, path)
    assert "stands:" not in out
    assert re.search(r"warning: with its targets held .* it falls at 0\.\d+ s", err), err
    m = re.search(r"ankle carries 0.7 kg standing on it: stiffness 1 N\*m/rad against "
                  r"m\*g\*h = ([\d.]+)", err)
    assert m and 1.5 < float(m.group(1)) < 1.8, err  # 0.7 kg * 9.81 * ~0.24 m


def test_a_weak_ankle_is_told_to_raise_its_torque_limit(tmp_path, capsys):
    path = lamp(tmp_path, "weak", ankle="pd: {stiffness: 18.0, damping: 0.3, max_torque: 0.1}")
    out, err = check(capsys, path)
    assert "it falls at" in err and "joint 'ankle' is at its torque limit" in err
    assert "ankle cannot hold the 0.7 kg it carries" in err


def test_an_undamped_lamp_oscillates_and_the_joints_are_named(tmp_path, capsys):
    path = lamp(tmp_path, "wobbly", ankle="pd: {stiffness: 18.0, damping: 0.0, max_torque: 14.0}",
                knee="pd: {stiffness: 40.0, damping: 0.0, max_torque: 9.0}")
    out, err = check(capsys, path)
    assert "stands:" in out  # it stands, but does not come to rest
    swings = dict(re.findall(r"joint '(\w+)' oscillates: \+-[\d.]+ deg at ([\d.]+) Hz", err))
    assert set(swings) == {"ankle", "knee"} and float(swings["knee"]) > float(swings["ankle"])
    assert "still moving at the end" in out


def test_heavy_damping_on_a_light_link_is_reported_locked(tmp_path, capsys):
    path = lamp(tmp_path, "locked", ankle="pd: {stiffness: 18.0, damping: 3.0, max_torque: 14.0}")
    out, err = check(capsys, path)
    m = re.search(r"joint 'ankle': damping locks it against the light link 'lower_arm' "
                  r".*e\^-([\d.]+) .*damping ([\d.]+) or less tracks", err)
    assert m, err
    lam, track = float(m.group(1)), float(m.group(2))
    # lam = damping * dt * (1/I_a + 1/I_b), and the damping that tracks gives lam = 3
    assert math.isclose(3.0 * 3.0 / track, lam, rel_tol=0.02) and lam > 6.5


def test_a_bent_joint_softer_than_its_load_is_told_the_stiffness_it_needs(tmp_path, capsys):
    """Luxo's knee (bent 55 deg) at stiffness 3: above m*g*h (0.65), but the shade's
    weight pulls with 0.23 N*m and bends it 4 deg: the report says so, and what stiffness
    keeps it within 2 deg (30x the torque)."""
    path = lamp(tmp_path, "soft-knee", knee="pd: {stiffness: 3.0, damping: 0.05, max_torque: 9.0}")
    out, err = check(capsys, path)
    m = re.search(r"knee gives about (\d+) deg under the 0.45 kg it carries \(its weight pulls "
                  r"with ([\d.]+) N\*m, stiffness 3 N\*m/rad.*stiffness ([\d.]+)", err)
    assert m, err
    assert 3 <= int(m.group(1)) <= 6
    assert float(m.group(3)) == pytest.approx(float(m.group(2)) / math.radians(2), rel=0.02)
    assert "balance at the start: centre of mass at x " in out
