"""A mapping's channels against the character it plays on: a channel that is no joint
of it (a typo) is an error with a did-you-mean, at the channel's line, in play and in
``puppet check``; a mapping none of whose channels is a joint is refused."""

from __future__ import annotations

from pathlib import Path

import pytest

from puppet.commands import main

CMU = Path("assets/mappings/cmu-131.yaml").read_text(encoding="utf-8")


def _typo(tmp_path, text=CMU) -> Path:
    path = tmp_path / "typo.yaml"
    path.write_text(text.replace("  knee_near:", "  knee_naer:"), encoding="utf-8")
    return path


def _line_of(path: Path, text: str) -> int:
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_check_refuses_a_channel_no_joint_of_the_mappings_character(tmp_path, capsys):
    path = _typo(tmp_path)
    assert "character: biped" in path.read_text()
    assert main(["check", str(path)]) != 0
    err = capsys.readouterr().err.strip()
    assert f"typo.yaml:{_line_of(path, 'knee_naer')}:" in err, err
    assert "'knee_naer'" in err and "did you mean 'knee_near'?" in err and "\n" not in err


def test_check_of_a_mapping_naming_no_character_cannot_tell(tmp_path, capsys):
    path = _typo(tmp_path, CMU.replace("character: biped\n", ""))
    assert main(["check", str(path)]) == 0  # which joints it is for, it does not say


def test_play_refuses_a_channel_no_joint_of_the_character(tmp_path, capsys):
    path = _typo(tmp_path, CMU.replace("character: biped\n", ""))
    code = main(["play", "biped-mocap", "--headless", "--mocap", "cmu-131_01-walk",
                 "--mapping", str(path)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and f"typo.yaml:{_line_of(path, 'knee_naer')}:" in err, err
    assert "is no joint of biped; did you mean 'knee_near'?" in err and "\n" not in err


def test_check_of_an_interface_holds_its_mappings_channels_to_its_character(tmp_path, capsys):
    _typo(tmp_path, CMU.replace("character: biped\n", ""))
    text = Path("interfaces/biped-mocap.yaml").read_text(encoding="utf-8")
    interface = tmp_path / "mine.yaml"
    interface.write_text(text.replace("mapping: cmu-131", "mapping: typo.yaml"),
                         encoding="utf-8")
    assert main(["check", str(interface)]) != 0
    err = capsys.readouterr().err.strip()
    assert "mine.yaml:" in err and "did you mean 'knee_near'?" in err, err


def test_play_refuses_a_mapping_that_drives_none_of_the_characters_joints(capsys):
    code = main(["play", "luxo-mouse", "--headless", "--mocap", "cmu-131_01-walk",
                 "--mapping", "cmu-131"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "no channel of mapping 'cmu-131'" in err, err
    assert "is a joint of luxo (ankle, knee)" in err and "\n" not in err


def test_no_mapping_fits_luxo_so_none_is_suggested(capsys):
    code = main(["play", "luxo-mouse", "--headless", "--mocap", "cmu-131_01-walk"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "no mapping of assets/mappings/ fits luxo" in err, err
    assert "--mapping NAME" not in err
    code = main(["play", "biped-stand", "--headless", "--mocap", "cmu-131_01-walk"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "--mapping NAME (" in err and "cmu-131" in err, err


@pytest.mark.parametrize("name", ["cmu-01", "cmu-131", "mediapipe-pose", "vmc-humanoid"])
def test_the_shipped_mappings_name_their_character_and_pass(name, capsys):
    path = f"assets/mappings/{name}.yaml"
    assert "character: biped" in Path(path).read_text()
    assert main(["check", path]) == 0


def test_play_with_a_clip_the_mapping_does_not_fit_suggests_the_one_info_picks(capsys):
    """--mapping given, and it does not fit (without --mapping the interface's
    mapping that does not fit gives way to the one info picks: test_mocap_rigs)."""
    from puppet.mocap.bvh import read_bvh
    from puppet.mocap.info import matching_mappings

    picked = matching_mappings(read_bvh("assets/mocap/cmu-01_01-jumps.bvh"))[0][0]
    code = main(["play", "biped-mocap", "--headless", "--mocap", "cmu-01_01-jumps",
                 "--mapping", "cmu-131"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and f"--mapping {picked} (shipped)" in err and picked == "cmu-01", err
    # what the source has: all of it (counted), not only the names the mapping reads
    assert "the source has 31 points: Hips, LHipJoint, LeftUpLeg" in err, err
    assert "\n" not in err


def test_a_mistyped_joint_of_a_mapping_gets_a_did_you_mean(tmp_path, capsys):
    path = tmp_path / "kne.yaml"
    path.write_text(CMU.replace("to: RightKnee}", "to: RightKne}"), encoding="utf-8")
    code = main(["play", "biped-mocap", "--headless", "--mocap", "cmu-131_01-walk",
                 "--mapping", str(path)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "no point named RightKne (did you mean RightKnee?)" in err, err


def test_what_the_docs_say_cmu_01_differs_in_is_what_it_differs_in():
    """cmu-01 against cmu-131 with subject 1's joint names put back: every other field
    that differs is one the mocap page and the guide name, with its value."""
    import re

    from puppet.data.mappings import load_mapping

    a = load_mapping("assets/mappings/cmu-131.yaml")
    b = load_mapping("assets/mappings/cmu-01.yaml")
    # (the fields that hold no joint names; the others differ by them)
    differ = [f for f in ("source", "plane", "size", "channels") if getattr(a, f) != getattr(b, f)]
    assert "plane" in differ and "size" in differ  # (what the files hold today)
    from tests.test_docs import guide_pages

    guide = " ".join(p.read_text(encoding="utf-8") for p in guide_pages())
    for doc, text in (("docs/mocap.md", Path("docs/mocap.md").read_text(encoding="utf-8")),
                      ("the guide", guide)):
        text = " ".join(text.split())
        said = re.search(r"`(?:assets/mappings/)?cmu-01\.yaml` is [^)]*?\)[^.;]*", text)
        assert said, doc
        for field in differ:
            assert f"`{field}" in said.group(0), (doc, field, said.group(0))
        assert f"{b.size:g}" in said.group(0) and f"plane: {b.plane}" in said.group(0)
