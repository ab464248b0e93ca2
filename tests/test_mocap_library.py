"""Zordan's search (issue 30): ``puppet mocap library FOLDER`` indexes BVH clips into a
motion library; after a push the tracker searches it for the window nearest the
figure's state, follows it, and gives the figure back to the performer. The log
(assets/logs/biped-mocap-library) keeps its feet after the shove that fells
biped-mocap, and fails without the library; the search replays to the bit; bad
folders, clips and library files are one line."""

from __future__ import annotations

import dataclasses
import json
import math
import shutil

import numpy as np
import pytest

from puppet.commands import main
from puppet.data.catalog import find, load_setup
from puppet.data.errors import DataError
from puppet.data.motion_library import load_library
from puppet.interface import events as ev
from puppet.mocap.clip_source import ClipSource
from puppet.mocap.clips import open_clip
from puppet.mocap.library import index_folder, write_library
from puppet.mocap.retarget import load_mapping
from puppet.session import Session
from puppet.testing import replay_log

LOG = "assets/logs/biped-mocap-library.jsonl"
WALK = find("clip", "cmu-131_01-walk")
LEGS = ["hip_near", "knee_near", "hip_far", "knee_far"]


@pytest.fixture(scope="module")
def walk_only(tmp_path_factory):
    folder = tmp_path_factory.mktemp("clips")
    shutil.copy(WALK, folder / "walk.bvh")
    return folder


def test_a_folder_is_indexed_into_windows_with_features(walk_only, tmp_path):
    doc = index_folder(walk_only, window=1.0, hop=0.25)
    assert [c["name"] for c in doc["clips"]] == ["walk"]
    assert doc["trunk_link"] == "chest" and "hip_near" in doc["joints"]
    assert ["hip_near", "hip_far"] in doc["mirror"]
    windows = doc["windows"]
    assert {w["mirrored"] for w in windows} == {False, True}
    assert len(windows) == 2 * len([w for w in windows if not w["mirrored"]])
    out = tmp_path / "lib.json"
    write_library(doc, out)
    lib = load_library(out)
    assert len(lib.windows) == len(windows) and lib.frames == 31
    assert len(lib.windows[0].features) == 4 + len(lib.joints)
    # a mirrored window swaps near and far: its hip_near is the plain one's hip_far
    plain = next(i for i, w in enumerate(lib.windows) if not w.mirrored and w.start == 64)
    mirror = next(i for i, w in enumerate(lib.windows) if w.mirrored and w.start == 64)
    a, b = lib.channels_at(plain, 0.5), lib.channels_at(mirror, 0.5)
    assert a["hip_near"] == b["hip_far"] and a["root.x"] == b["root.x"]
    # the walk goes forward about 0.3 m/s at its start... and over 1 m/s in mid-walk
    speeds = [lib.windows[i].features[2] for i in range(len(lib.windows))]
    assert max(speeds) > 1.0


def test_the_shipped_library_is_the_index_of_the_shipped_clips():
    shipped = load_library(find("library", "cmu-library"))
    fresh = index_folder(find("clip", "cmu-131_01-walk").parent)
    assert [c["name"] for c in fresh["clips"]] == [c[0] for c in shipped.clips]
    assert len(fresh["windows"]) == len(shipped.windows) == 768
    worst = max(abs(a - b) for w, s in zip(fresh["windows"], shipped.windows)
                for a, b in zip([w["trunk"], w["spin"], *w["com"], *w["q"]], s.features))
    assert worst < 1e-4


def test_bad_folders_and_clips_are_one_line(tmp_path, capsys):
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["mocap", "library", str(empty)]) == 2
    err = capsys.readouterr().err
    assert "no .bvh clips in this folder" in err and err.count("\n") == 1
    assert main(["mocap", "library", str(tmp_path / "nowhere")]) == 2
    assert "not a folder" in capsys.readouterr().err
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "broken.bvh").write_text("HIERARCHY\nROOT Hips\n{\n", encoding="utf-8")
    assert main(["mocap", "library", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "no clip could be used" in err and "broken.bvh" in err and err.count("\n") == 1
    shutil.copy(WALK, bad / "walk.bvh")  # one good clip: the broken one skipped, said
    out = tmp_path / "lib.json"
    assert main(["mocap", "library", str(bad), "--out", str(out), "--hop", "0.5"]) == 0
    said = capsys.readouterr()
    assert "warning: skipped broken.bvh" in said.err and "from 1 clip(s) (walk)" in said.out
    assert load_library(out).clips[0][0] == "walk"


@pytest.mark.parametrize("text, says", [
    ("not json at all", "not JSON"),
    ('{"format": "something-else"}', "not a motion library"),
    ('{"format": "puppet-motion-library", "version": 7}', "version 7"),
    ('{"format": "puppet-motion-library", "version": 1}', "malformed motion library"),
    ("[1, 2]", "not a motion library"),
])
def test_absurd_library_files_are_one_line(tmp_path, text, says):
    path = tmp_path / "x.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(DataError) as err:
        load_library(path)
    assert says in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize("change, says", [
    (lambda d: d["windows"][3].update(start=10**6), "runs past its clip's frames"),
    (lambda d: d["windows"][0].update(trunk=float("nan")), "finite number"),
    (lambda d: d["windows"][0].update(clip=5), "clip's index"),
    (lambda d: d["clips"][0]["frames"][2].append(1.0), "list of"),
    (lambda d: d.update(rate=1e9), "rate"),
    (lambda d: d.update(windows=[]), "at least one window"),
    (lambda d: d.update(joints=["tail"]), "no 'tail'"),
])
def test_a_library_with_bad_numbers_is_one_line(walk_only, tmp_path, change, says):
    doc = index_folder(walk_only, hop=0.5)
    change(doc)
    path = tmp_path / "x.json"
    path.write_text(json.dumps(doc), encoding="utf-8")  # (nan as NaN: json reads it)
    with pytest.raises(DataError) as err:
        load_library(path)
    assert says in str(err.value) and "\n" not in str(err.value)


def test_an_interface_naming_no_library_is_one_line(tmp_path):
    text = find("interface", "biped-mocap-library").read_text(encoding="utf-8")
    path = tmp_path / "x.yaml"
    path.write_text(text.replace("file: cmu-library", "file: no-such-library"),
                    encoding="utf-8")
    with pytest.raises(DataError) as err:
        load_setup(str(path))
    said = str(err.value)
    assert "no motion library named 'no-such-library'" in said and "cmu-library" in said
    assert "\n" not in said and ":3" in said.split(": ")[0] or "x.yaml:" in said


def _without_library(setup):
    tracking = setup.interface.tracking
    reaction = tracking.reaction.model_copy(update={"library": None})
    return dataclasses.replace(setup, interface=setup.interface.model_copy(
        update={"tracking": tracking.model_copy(update={"reaction": reaction})}))


def test_the_log_keeps_its_feet_and_fails_without_the_library():
    result = replay_log(LOG)
    assert not result.failed, [str(f) for f in result.failed]
    old = replay_log(LOG, adjust=_without_library)  # the pulls let go: it falls
    kinds = {f.kind for f in old.failed}
    assert {"never_fell", "height_at_end"} <= kinds, [str(f) for f in old.failed]


@pytest.fixture(scope="module")
def walk_clip():
    return open_clip("cmu-131_01-walk", load_mapping(find("mapping", "cmu-131")))


def _run(session, events, until):
    from puppet.session.playback import play

    play(session, [e for e in events if session.steps <= e[0] < until], until)


def _shoved(walk_clip, until: float):
    s = Session(load_setup("biped-mocap-library"))
    dt = s.sim.dt
    events = ClipSource(walk_clip).events(dt, 8.3)
    _run(s, events, round(5.3 / dt))
    s.handle(ev.key("shift+]", True))
    _run(s, events, round(5.35 / dt))
    s.handle(ev.key("shift+]", False))
    _run(s, events, round(until / dt))
    return s, events


def test_the_figure_follows_the_window_found_then_the_performer(walk_clip):
    s, events = _shoved(walk_clip, 5.9)
    tracker = s.runtime.tracker
    assert tracker.reaction[0] == "fall" and tracker.searches == 1
    index = tracker.lib[0]
    lib = tracker.library
    assert lib.window_name(index) == "cmu-131_01-walk at 4.70 s (mirrored)"
    assert "reacting via library window" in tracker.status
    # the joint targets are the window's (blended in by now), not the performer's
    written = (s.steps - 1) // tracker.every * tracker.every  # the last control step
    window = lib.channels_at(index, (written - tracker.lib[1]) * s.sim.dt)
    servos = s.character.servos
    performer = s.runtime.channels
    for joint in LEGS:
        target = math.degrees(servos[joint].target)
        assert target == pytest.approx(window[joint], abs=0.01)
        assert abs(target - performer[joint]) > 1.0
    _run(s, events, round(7.0 / s.sim.dt))
    assert tracker.lib is None and tracker.reaction is None and tracker.getup is None
    assert s.character.upright()


def test_a_checkpoint_in_mid_window_replays_to_the_bit(walk_clip):
    s, events = _shoved(walk_clip, 5.6)
    assert s.runtime.tracker.lib is not None
    s.checkpoint()
    _run(s, events, round(6.5 / s.sim.dt))
    first = s.sim.state_hash()
    s.restore_checkpoint()
    assert s.runtime.tracker.lib is not None
    _run(s, events, round(6.5 / s.sim.dt))
    assert s.sim.state_hash() == first


def test_the_search_weighs_the_trunk_high():
    """Two windows alike but for the trunk: the one whose trunk matches wins, however
    the joints differ."""
    from types import SimpleNamespace

    from puppet.data.motion_library import Window
    from puppet.data.tracking import SearchWeightsSpec
    from puppet.interface.controllers.tracking_library import LibraryReactions

    class Probe(LibraryReactions):
        def __init__(self, me, windows):
            self.me = me
            self.library = SimpleNamespace(windows=windows)
            self.spec = SimpleNamespace(reaction=SimpleNamespace(
                library=SimpleNamespace(weights=SearchWeightsSpec())))

        def figure_features(self):
            return self.me

    me = (0.3, 1.0, 1.2, 0.0, 0.1, 0.1)
    near_trunk = Window(0, 0, False, (0.3, 1.0, 1.2, 0.0, 0.5, -0.3))
    near_joints = Window(0, 0, False, (-0.1, 0.0, 1.2, 0.0, 0.1, 0.1))
    assert Probe(me, [near_joints, near_trunk]).search()[0] == 1
    # a whole turn away is the same trunk angle
    turned = Window(0, 0, False, (0.3 + 2 * math.pi, 1.0, 1.2, 0.0, 0.1, 0.1))
    assert Probe(me, [near_trunk, turned]).search()[0] == 1
    assert np.isclose(Probe(me, [turned]).search()[1], 0.0)
