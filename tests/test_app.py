"""The command line and the headless app, as a user runs them."""

import subprocess
import sys

import pygame
import pytest

from puppet.commands.check import check_file
from puppet.data import catalog


def puppet(*args):
    return subprocess.run([sys.executable, "-m", "puppet", *args], capture_output=True,
                          text=True)


def test_help_lists_every_command():
    out = puppet("--help").stdout
    for command in ("play", "list", "check"):
        assert command in out


def test_list_shows_each_kind_with_descriptions():
    out = puppet("list").stdout
    assert "luxo" in out and "luxo-mouse" in out and "ski-jump" in out
    assert "desk lamp" in out


SHIPPED = sorted(
    list((catalog.ROOT / "characters").glob("*.yaml"))
    + list((catalog.ROOT / "interfaces").glob("*.yaml"))
    + list((catalog.ROOT / "assets" / "scenes").glob("*.yaml"))
    + list((catalog.ROOT / "assets" / "scripts").glob("*.yaml"))
    + list((catalog.ROOT / "assets" / "mappings").glob("*.yaml"))
    + list((catalog.ROOT / "assets" / "logs").glob("*.expect.yaml")))


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_every_shipped_file_is_valid(path):
    kind = check_file(path)
    assert (kind == "expectations") == path.name.endswith(".expect.yaml"), kind


@pytest.mark.parametrize("scene", [n for n, _ in catalog.list_kind("scene")])
def test_luxo_rests_on_every_scene(scene):
    from puppet.session import Session

    session = Session(catalog.load_setup("luxo-mouse", scene))
    session.advance(2 * 480)
    assert not session.sim.blown_up()
    assert session.character.upright()


def test_headless_screenshot_shows_the_lamp(tmp_path):
    shot = tmp_path / "shot.png"
    proc = puppet("play", "luxo-mouse", "--headless", "--seconds", "0.5", "--screenshot",
                  str(shot))
    assert proc.returncode == 0, proc.stderr
    image = pygame.image.load(str(shot))
    assert image.get_size() == (1280, 720)
    # The lamp's base colour is drawn where the camera puts the character (a little left
    # of the middle: LEAD_X), above the floor.
    from puppet.app.camera import LEAD_X

    w, h = image.get_size()
    at = round(w * (0.5 - LEAD_X))
    colours = {tuple(image.get_at((x, y)))[:3] for x in range(at - 80, at + 80, 2)
               for y in range(h // 2, h - 60, 2)}
    assert (70, 80, 96) in colours


def test_app_keys_clash_is_reported_and_rebinding_fixes_it(tmp_path):
    from puppet.data.errors import DataError
    from puppet.data.interfaces import parse_interface
    from puppet.data.yamlfile import load_text

    text = "name: x\ndescription: x\ncharacter: luxo\nkeys:\n  - {key: p, set: {knee: 10}}\n"
    with pytest.raises(DataError) as info:
        parse_interface(load_text(text, "x.yaml"))
    assert info.value.line == 5 and "'pause'" in info.value.message
    spec = parse_interface(load_text(text + "app_keys: {pause: f5}\n", "x.yaml"))
    assert spec.app_key_table()["pause"] == "f5"


def test_a_script_plays_on_the_scene_it_was_written_for():
    proc = puppet("play", "luxo-mouse", "--headless", "--input", "luxo-ski-jump")
    assert proc.returncode == 0, proc.stderr
    x = float(proc.stdout.split("com=(")[1].split(",")[0])
    assert x > 8.0  # down the ski jump, not hopping about on the flat floor
    other = puppet("play", "luxo-keys", "--headless", "--input", "luxo-hop", "--seconds", "0.1")
    assert "written for interface 'luxo-mouse'" in other.stderr


def test_scripted_events_after_the_end_of_the_run_are_reported(tmp_path):
    script = tmp_path / "late.yaml"
    script.write_text("description: late\nevents:\n  - {t: 0.5, mouse: [0.5, 0.5]}\n"
                      "  - {t: 9.0, key: a}\n")
    proc = puppet("play", "luxo-mouse", "--headless", "--input", str(script))
    assert proc.returncode == 0
    assert ("1 of the script's 2 entries starts after the run ends and never acts: the run "
            "ends at 5 s (the default: neither --seconds nor 'seconds:' in the script says); "
            "the script's last entry is at t = 9 s") in proc.stderr, proc.stderr


def test_late_entries_are_counted_as_written_and_the_script_says_how_long_it_runs():
    """luxo-hop has 6 entries after 1.1 s (glides of many mouse samples each): the
    warning counts those 6, not the 259 events they compile to, and says how long the
    script runs instead of telling the user to set the --seconds they just set."""
    proc = puppet("play", "luxo-mouse", "--headless", "--input", "luxo-hop", "--seconds", "1.1")
    assert proc.returncode == 0, proc.stderr
    assert ("warning: 6 of the script's 9 entries start after the run ends and never act: "
            "the run ends at 1.1 s (--seconds); the script's last entry is at t = 3.5 s and "
            "it is done at 3.8 s") in proc.stderr, proc.stderr
    assert "259" not in proc.stderr and "set 'seconds:'" not in proc.stderr


def test_late_note_counts_entries_and_entries_cut_short():
    from puppet.physics.simulation import DEFAULT_DT as dt
    from puppet.timeline.script import ScriptEntry, ScriptSpec, late_note

    spec = ScriptSpec(seconds=2.0, events=[
        ScriptEntry(t=0.0, mouse=(0.5, 0.5)),
        ScriptEntry(t=1.9, mouse=(0.2, 0.2), over=0.5),  # a glide past the end
        ScriptEntry(t=2.0, key="a"),  # at the end's own step: it acts
        ScriptEntry(t=2.5, key="b", hold=0.5),  # a press and its release: one entry
        ScriptEntry(t=3.0, action="reset")])
    note = late_note(spec, 2.0, dt)
    assert note.startswith("2 of the script's 5 entries start after the run ends and never "
                           "act, 1 is cut short by the end (a glide or hold that goes on "
                           "past it): the run ends at 2 s (the script's 'seconds:')"), note
    assert note.endswith("the script's last entry is at t = 3 s"), note
    assert late_note(spec, 3.0, dt) is None  # the 0.5 s hold of 'b' is done at 3 s
    assert late_note(spec, 2.9, dt, given=True) == (
        "1 of the script's 5 entries starts after the run ends and never acts, 1 is cut "
        "short by the end (a glide or hold that goes on past it): the run ends at 2.9 s "
        "(--seconds); the script's last entry is at t = 3 s")
