"""``puppet check`` takes what the other commands take: names (looked up in every catalog
folder, since check does not say the kind), input logs (read as ``puppet replay`` reads
them, the first problem in its words) and BVH clips (as ``puppet mocap info`` reads
them); anything else is told what check reads."""

from __future__ import annotations

import json

from puppet.commands import main
from puppet.data.catalog import ROOT, file_hash
from puppet.timeline.log import text_hash

HOP = ROOT / "assets" / "logs" / "luxo-hop.jsonl"
WALK = ROOT / "assets" / "mocap" / "cmu-131_01-walk.bvh"
READS = ("puppet check reads .yaml data files (characters, interfaces, scenes, scripts, "
         "mocap mappings, bone tables, logs' NAME.expect.yaml, tuning specs), .jsonl logs, "
         ".bvh clips and .json motion libraries, or their names")


def run(capsys, *argv):
    code = main(["check", *map(str, argv)])
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    return code, captured.out, captured.err


def lines_of(path):
    return path.read_text(encoding="utf-8").splitlines()


def write(path, lines):
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_a_log_and_a_clip_are_checked_as_replay_and_mocap_info_read_them(capsys):
    assert run(capsys, HOP, WALK) == (0, f"{HOP}: ok (log)\n{WALK}: ok (mocap clip)\n", "")
    logs = sorted((ROOT / "assets" / "logs").glob("*.jsonl"))
    code, out, err = run(capsys, "-q", *logs)
    assert (code, out, err) == (0, "", "")


def test_names_are_looked_up_in_every_folder_and_an_ambiguous_one_is_refused(
        capsys, monkeypatch, tmp_path):
    names = ("luxo-mouse", "luxo", "cmu-131_01-walk", "biped-mocap-live", "flat")
    files = ["interfaces/luxo-mouse.yaml: ok (interface)", "characters/luxo.yaml: ok "
             "(character)", "assets/mocap/cmu-131_01-walk.bvh: ok (mocap clip)",
             "assets/logs/biped-mocap-live.jsonl: ok (log)", "assets/scenes/flat.yaml: ok "
                                                             "(scene)"]
    monkeypatch.chdir(tmp_path)  # outside the checkout: the absolute paths
    code, out, _ = run(capsys, "--no-stability", *names)  # (luxo's report: test_stability)
    assert code == 0
    assert out.splitlines() == [f"{ROOT}/{f}" for f in files]
    monkeypatch.chdir(ROOT)  # in it: the paths from here (each opens its file)
    code, out, _ = run(capsys, "--no-stability", *names)
    assert (code, out.splitlines()) == (0, files)
    code, out, err = run(capsys, "luxo-hop")
    assert (code, out) == (2, "")
    assert err == ("puppet check: luxo-hop: ambiguous name: a script (assets/scripts/"
                   "luxo-hop.yaml) and a log (assets/logs/luxo-hop.jsonl); give the path\n")
    code, _, err = run(capsys, "no-such-thing")
    assert code == 2 and err.startswith("puppet check: no-such-thing: no such file, and no "
                                        "name of the catalog (characters/, interfaces/, "), err


def test_other_files_are_told_what_check_reads(capsys, tmp_path):
    notes = write(tmp_path / "notes.md", ["# notes"])
    bare = write(tmp_path / "luxo", ["links: []"])
    assert run(capsys, notes) == (2, "", f"puppet check: {notes}: cannot check '.md' files; "
                                         f"{READS}\n")
    assert run(capsys, bare) == (2, "", f"puppet check: {bare}: cannot check a file with no "
                                        f"extension; {READS}\n")
    assert run(capsys, tmp_path) == (2, "", f"puppet check: {tmp_path}: is a folder; {READS}\n")
    missing = tmp_path / "gone.jsonl"
    assert run(capsys, missing) == (2, "", f"puppet check: {missing}: no such file\n")


def _replay_error(capsys, path, *options) -> str:
    assert main(["replay", str(path), "--headless", *options]) == 2
    err = capsys.readouterr().err
    assert err.startswith("puppet replay: ") and err.count("\n") == 1, err
    return err.removeprefix("puppet replay: ")


def test_a_broken_log_gives_the_replays_first_problem(capsys, tmp_path):
    lines = lines_of(HOP)
    bad_line = write(tmp_path / "bad-line.jsonl",
                     lines[:3] + ['{"step": 200, "event": {"type": "mouse", "x": 0.5}}']
                     + lines[3:])
    header = json.loads(lines[0])
    header["scene"] = "no-such-scene"
    bad_header = write(tmp_path / "bad-header.jsonl", [json.dumps(header)] + lines[1:])
    reload = {"step": 148, "event": {"type": "reload", "text": "name: x\ncharacter: luxo\n"
                                                               "maps: 3\n"}}
    bad_reload = write(tmp_path / "bad-reload.jsonl", lines[:4] + [json.dumps(reload)]
                       + lines[4:])
    for path, words in ((bad_line, f"{bad_line}:4: "), (bad_header, f"{bad_header}:1: "),
                        (bad_reload, f"{bad_reload}:5: cannot apply this event: ")):
        expected = _replay_error(capsys, path)
        assert expected.startswith(words), expected
        # (replay's option, said as the command: check has no --allow-truncated)
        expected = expected.replace("(--allow-truncated", "(puppet replay --allow-truncated")
        assert run(capsys, path) == (2, "", f"puppet check: {expected}")


def test_a_logs_expectations_are_checked_with_it(capsys, tmp_path):
    log = write(tmp_path / "hop.jsonl", lines_of(HOP))
    side = write(tmp_path / "hop.expect.yaml",
                 ["expect:", "  - never_fell: true", "  - height_at_end: {link: lampshade, "
                                                     "min: 0.1}"])
    expected = _replay_error(capsys, log, "--check")  # replay reads them with --check
    assert expected.startswith(f"{side}:3:"), expected
    assert "unknown link 'lampshade'" in expected
    assert run(capsys, log) == (2, "", f"puppet check: {expected}")
    write(side, ["expect:", "  - never_fell: true"])
    assert run(capsys, log) == (0, f"{log}: ok (log)\n", "")


def test_what_a_replay_warns_about_a_log_check_warns_about_too(capsys, tmp_path):
    """A log with no expectations (a take the window recorded, then killed) plays in a
    plain replay: ok, warned in check's words (check does not replay it) that replay
    --check refuses it."""
    cut = write(tmp_path / "cut.jsonl", lines_of(HOP)[:-1])  # no end line: killed?
    code, out, err = run(capsys, cut)
    assert (code, out) == (0, f"{cut}: ok (log)\n")
    assert err == (f"{cut}: warning: no end line (the recording did not close: killed or "
                   f"crashed?); puppet replay plays its 303 events with no recorded end "
                   f"state to compare, and replay --check refuses it\n"), err
    assert "replaying" not in err


def test_a_log_with_expectations_and_no_end_line_is_refused_as_replay_check_refuses_it(
        capsys, tmp_path):
    """Its expectations make it a test for ``puppet replay --check``, which refuses it
    (exit 2): check says so, in the same words at the same line (the log's last: there
    is no line after it), with the command to run instead of the option it has not."""
    for where in ("sidecar", "header"):
        lines = lines_of(HOP)[:-1]
        cut = tmp_path / where / "cut.jsonl"
        cut.parent.mkdir()
        if where == "sidecar":
            write(tmp_path / where / "cut.expect.yaml", ["expect:", "  - never_fell: true"])
        else:
            header = json.loads(lines[0])
            header["expect"] = [{"never_fell": True}]
            lines[0] = json.dumps(header)
        write(cut, lines)
        replayed = _replay_error(capsys, cut, "--check")
        assert replayed.startswith(f"{cut}:{len(lines)}: no end line"), replayed
        code, out, err = run(capsys, cut)
        assert (code, out) == (2, ""), err
        assert err == "puppet check: " + replayed.replace(
            "(--allow-truncated checks", "(puppet replay --headless --check "
                                        "--allow-truncated checks"), err
        assert ("(puppet replay --headless --check --allow-truncated checks the expectations "
                "on its 303 events, to step 1824, without the end state)\n") in err, err
        assert run(capsys, "-q", cut)[0] == 2


def test_a_log_cut_mid_line_names_the_replay_option_as_a_command(capsys, tmp_path):
    """check has no --allow-truncated: its hint names ``puppet replay --allow-truncated``."""
    text = HOP.read_text(encoding="utf-8")
    cut = tmp_path / "mid.jsonl"
    cut.write_text(text[:-30], encoding="utf-8")
    replayed = _replay_error(capsys, cut)
    assert replayed.endswith(" (--allow-truncated replays the lines before it)\n"), replayed
    code, out, err = run(capsys, cut)
    assert (code, out) == (2, "")
    assert err == "puppet check: " + replayed.replace(
        "(--allow-truncated", "(puppet replay --allow-truncated"), err


def test_a_broken_clip_is_a_line_of_the_bvh_reader(capsys, tmp_path):
    text = WALK.read_text(encoding="utf-8").replace("CHANNELS 6", "CHANNELS six", 1)
    clip = tmp_path / "walk.bvh"
    clip.write_text(text, encoding="utf-8")
    code, out, err = run(capsys, clip)
    assert (code, out) == (2, "") and err.startswith(f"puppet check: {clip}:5"), err


def test_a_file_found_by_name_is_named_alike_when_ok_and_in_its_errors(capsys, monkeypatch,
                                                                       tmp_path):
    from puppet.data import catalog

    (tmp_path / "characters").mkdir()
    good = (ROOT / "characters" / "luxo.yaml").read_text(encoding="utf-8")
    (tmp_path / "characters" / "luxo.yaml").write_text(good, encoding="utf-8")
    (tmp_path / "characters" / "bad.yaml").write_text("name: bad\nlinks: 3\n",
                                                      encoding="utf-8")
    monkeypatch.setattr(catalog, "ROOT", tmp_path)
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "--no-stability", "luxo", "bad")
    assert code == 2
    assert out == "characters/luxo.yaml: ok (character)\n"
    assert err.startswith("puppet check: characters/bad.yaml:2:"), err
    monkeypatch.chdir(ROOT)  # the catalog elsewhere: its absolute paths, both
    code, out, err = run(capsys, "--no-stability", "luxo", "bad")
    assert out == f"{tmp_path}/characters/luxo.yaml: ok (character)\n"
    assert err.startswith(f"puppet check: {tmp_path}/characters/bad.yaml:2:"), err


def test_checks_words_about_a_logs_interface_say_what_a_replay_would_do(capsys, tmp_path):
    """check does not replay: its notes and hints say what ``puppet replay`` would do and
    name that command's option (check has no --as-recorded)."""
    def log_with(name, **changes):
        lines = lines_of(HOP)
        header = json.loads(lines[0])
        header.update(changes)
        return write(tmp_path / name, [json.dumps(header)] + lines[1:])

    gone = log_with("gone.jsonl", interface="no-such-interface")
    older = json.loads(lines_of(HOP)[0])["interface_text"] + "# an older version\n"
    older_hash = text_hash(older.encode())  # recorded from a file that has changed since
    changed = log_with("changed.jsonl", interface_text=older, interface_hash=older_hash)
    broken = write(tmp_path / "broken.yaml", ["name: broken", "description: x",
                                              "character: luxo", "maps: 5"])
    bad = log_with("bad.jsonl", interface=str(broken))
    code, out, err = run(capsys, gone, changed)
    assert (code, out) == (0, f"{gone}: ok (log)\n{changed}: ok (log)\n")
    today = file_hash(ROOT / "interfaces" / "luxo-mouse.yaml")
    assert err == (f"{gone}: note: interface file 'no-such-interface' is not found (in the "
                   f"catalog or the log's folder); the copy recorded in the log plays\n"
                   f"{changed}: warning: interface 'luxo-mouse': the file found "
                   f"({ROOT}/interfaces/luxo-mouse.yaml, hash {today}) differs from the one "
                   f"recorded (hash {older_hash}); the replay may end elsewhere (puppet "
                   f"replay --as-recorded replays the recorded interface)\n"), err
    code, out, err = run(capsys, bad)
    assert (code, out) == (2, "") and err.startswith(
        f"puppet check: {bad}:1: header: the files it names beside the log (broken.yaml) "
        "do not make a valid session"), err
    assert err.endswith("(puppet replay --as-recorded replays the log's own copy of the "
                        "interface)\n"), err
    assert "replaying" not in err


def test_a_script_is_checked_against_the_interface_it_names(tmp_path, capsys):
    """A script's rules name sensors, states and chains of its ``interface:``; check
    refuses a misspelt one at its line, as ``puppet play --input`` does, and a script
    whose interface it cannot find is checked on its own."""
    ladder = ROOT / "assets" / "scripts" / "biped-ladder-climb.yaml"
    assert run(capsys, ladder)[0] == 0
    lines = lines_of(ladder)
    at = next(i for i, line in enumerate(lines) if "held.hand_far" in line)
    lines[at] = lines[at].replace("held.hand_far", "held.hand_fra", 1)
    typo = write(tmp_path / "typo.yaml", lines)
    code, out, err = run(capsys, typo)
    assert code == 2 and err.startswith(f"puppet check: {typo}:{at + 1}:"), err
    assert "no chain 'hand_fra'" in err, err
    alone = write(tmp_path / "alone.yaml", ["interface: no-such-layout", "seconds: 1",
                                            "events:", "  - {t: 0.5, key: g}"])
    assert run(capsys, alone) == (0, f"{alone}: ok (script)\n", "")
