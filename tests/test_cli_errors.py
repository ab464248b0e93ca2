"""The command line as a newcomer meets it: every mistake is one line that begins
``puppet COMMAND:``, usage errors exit 2, and nothing is half done."""

import os
import subprocess
import sys

from puppet.data import catalog


def puppet(*args, env=None, cwd=None):
    return subprocess.run([sys.executable, "-m", "puppet", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, timeout=60)


def _no_display_env():
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER", "XDG_RUNTIME_DIR")}
    env["PYTHONPATH"] = str(catalog.ROOT)
    return env


def _recordings():
    folder = catalog.ROOT / "recordings"
    return set(folder.glob("*.jsonl")) if folder.exists() else set()


def test_play_without_a_display_says_so_points_to_headless_and_records_nothing(tmp_path):
    before = _recordings()
    proc = puppet("play", "luxo-mouse", env=_no_display_env())
    assert proc.returncode == 2
    line = proc.stderr.strip().splitlines()[-1]
    assert line.startswith("puppet play: no display found") and "--headless" in line
    assert proc.stderr.strip() == line  # one line: not SDL's "XDG_RUNTIME_DIR is invalid" first
    assert _recordings() == before
    log = tmp_path / "x.jsonl"
    proc = puppet("play", "luxo-mouse", "--record", str(log), env=_no_display_env())
    assert proc.returncode == 2 and not log.exists()


def test_a_window_replay_without_a_display_says_so_too_and_hints_at_replay(tmp_path):
    proc = puppet("replay", "luxo-hop", env=_no_display_env())
    assert proc.returncode == 2
    line = proc.stderr.strip().splitlines()[-1]
    assert line.startswith("puppet replay: no display found"), line
    assert line.endswith("; use --headless to replay without a window (e.g. puppet replay "
                         "luxo-hop --headless, or add --video out.mp4 to see it)"), line
    assert "puppet play" not in line
    mine = tmp_path / "my hop.jsonl"  # a log of one's own: its path, quoted for the shell
    mine.write_bytes((catalog.ROOT / "assets" / "logs" / "luxo-hop.jsonl").read_bytes())
    proc = puppet("replay", str(mine), env=_no_display_env())
    assert proc.returncode == 2
    assert f"(e.g. puppet replay '{mine}' --headless," in proc.stderr, proc.stderr


def _main_error(capsys, *argv):
    """Run ``puppet ARGV`` in this process: (exit code, the last stderr line)."""
    import pytest

    from puppet.commands import main

    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse's usage errors
        code = exc.code
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    if not lines:
        pytest.fail(f"no message, exit {code}")
    return code, lines[-1]


def test_output_paths_of_the_wrong_kind_are_refused_before_anything_runs(tmp_path, capsys):
    afile = tmp_path / "afile"
    afile.write_text("")
    cases = [
        (("--screenshot", str(tmp_path)), f"--screenshot {tmp_path}: is a folder; give a file "
                                          f"name ending in .png"),
        (("--screenshot", str(tmp_path / "shot")), "no extension; give a file name ending in"),
        (("--frames", str(afile)), f"--frames {afile}: is a file; give a folder"),
    ]
    for extra, fragment in cases:
        code, line = _main_error(capsys, "play", "luxo-mouse", "--headless", "--seconds",
                                 "0.1", *extra)
        assert code == 2 and line.startswith("puppet play: ") and fragment in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


def test_a_path_is_called_a_path_and_a_folder_a_folder(tmp_path, capsys):
    code, line = _main_error(capsys, "replay", "nosuch.jsonl", "--headless")
    assert code == 2 and line.startswith("puppet replay: nosuch.jsonl: no such file"), line
    assert "named" not in line
    code, line = _main_error(capsys, "replay", "nosuch", "--headless")
    assert code == 2 and "no log named 'nosuch'; known: " in line, line
    code, line = _main_error(capsys, "play", str(tmp_path), "--headless")
    assert code == 2 and line == (f"puppet play: {tmp_path}: is a folder; expected an "
                                  f"interface name or a .yaml file"), line
    code, line = _main_error(capsys, "replay", str(tmp_path), "--headless")
    assert code == 2 and line.startswith(f"puppet replay: {tmp_path}: is a folder"), line


def test_usage_errors_exit_2_with_the_command_named(capsys, tmp_path):
    cases = [
        (("play", "luxo-mouse", "--screenshot", "x.png"), "puppet play: --screenshot "
                                                          "and --frames need --headless"),
        (("replay", "luxo-hop", "luxo-backflip"), "puppet replay: several logs need --headless"),
        (("replay", "luxo-hop", "--check"), "puppet replay: --check needs --headless"),
        (("play", "luxo-mouse", "--headless", "--seconds", "-1"),
         "puppet play: argument --seconds: '-1' is not a duration from 0"),
        (("play", "luxo-mouse", "--headless", "--fps", "0"),
         "puppet play: argument --fps: '0' is not a frame rate"),
        (("replay", "luxo-hop", "--headless", "--jobs", "0"), "puppet replay: argument"),
        (("replay", "luxo-hop", "--headless", "--size", "10"),
         "puppet replay: argument --size: '10' is not WIDTHxHEIGHT"),
        (("replay", "luxo-hop", "--headless", "--until-step", "-5"),
         "puppet replay: argument --until-step"),
        (("check", str(tmp_path / "nosuch.yaml")), f"puppet check: {tmp_path}/nosuch.yaml: "),
        (("bench", "nosuch"), "puppet bench: no character named nosuch"),
    ]
    for argv, start in cases:
        code, line = _main_error(capsys, *argv)
        assert code == 2 and line.startswith(start), (argv, line)


def test_argparse_mistakes_are_one_line_naming_the_command_and_its_help(capsys):
    cases = [
        (("play", "luxo-mouse", "--headless", "--seconds", "-1"),
         "puppet play: argument --seconds: '-1' is not a duration from 0 to 86400 (simulated "
         "seconds) (puppet play --help)"),
        (("play",), "puppet play: the following arguments are required: interface "
                    "(puppet play --help)"),
        (("play", "luxo-mouse", "--bogus"),
         "puppet play: unrecognized arguments: --bogus (puppet play --help)"),
        (("replay", "luxo-hop", "--jobs", "x"), "puppet replay: argument --jobs/-j: 'x' is "
                                                "not a number of processes"),
        (("mocap", "send", "cmu-131_01-walk", "--speed", "99"),
         "puppet mocap send: argument --speed: '99' is not a speed from 0.05 to 10"),
        (("mocap", "listen", "--port", "x"),
         "puppet mocap listen: argument --port: invalid int value: 'x' "
         "(puppet mocap listen --help)"),
        (("mocap",), "puppet mocap: the following arguments are required: WHAT"),
        (("check", "-x", "a.yaml"), "puppet check: unrecognized arguments: -x"),
        (("bench", "--jsn"), "puppet bench: unrecognized arguments: --jsn"),
        (("nosuch",), "puppet: argument COMMAND: invalid choice: 'nosuch'"),
    ]
    from puppet.commands import main

    for argv, start in cases:
        try:
            code = main(list(argv))
        except SystemExit as exc:
            code = exc.code
        captured = capsys.readouterr()
        assert code == 2 and captured.out == "", (argv, captured.out)
        assert captured.err.count("\n") == 1 and captured.err.startswith(start), \
            (argv, captured.err)
        assert "usage:" not in captured.err and "error:" not in captured.err


def test_list_and_check_describe_their_arguments(capsys):
    from puppet.commands import main

    for argv, words in ((["list", "--help"], ["KIND", "only this kind", "recordings/"]),
                        (["check", "--help"], ["FILE", "YAML data file", "Exit 0"])):
        try:
            main(argv)
        except SystemExit as exc:
            assert exc.code == 0
        out = capsys.readouterr().out
        for word in words:
            assert word in out, (argv, out)


def test_list_takes_a_kind_singular_or_plural_as_its_headings_print_it(capsys):
    from puppet.commands import main

    assert main(["list", "interface"]) == 0
    singular = capsys.readouterr().out
    assert singular.startswith("interfaces (interfaces/):\n  ") and "luxo-mouse" in singular
    for word in ("interfaces", "Interfaces"):
        assert main(["list", word]) == 0
        assert capsys.readouterr().out == singular
    assert main(["list", "scenes"]) == 0
    assert capsys.readouterr().out.startswith("scenes (assets/scenes/):\n")
    code, line = _main_error(capsys, "list", "interfacess")
    assert code == 2 and line.startswith("puppet list: argument KIND: invalid choice: "
                                         "'interfacess'; did you mean 'interface'? (choose "
                                         "from 'character'"), line


def test_a_script_on_a_copy_of_its_interface_is_not_warned_about(tmp_path):
    """A script written for interface X plays on a copy of X's file (same ``name:``,
    another path) without the "written for another interface" warning; on an
    interface of another name it is warned about."""
    copy = tmp_path / "my-variant.yaml"
    copy.write_text((catalog.ROOT / "interfaces" / "luxo-mouse.yaml").read_text())
    same = puppet("play", str(copy), "--headless", "--input", "luxo-hop", "--seconds", "0.1")
    assert same.returncode == 0, same.stderr
    assert "was written for interface" not in same.stderr
    other = puppet("play", "luxo-keys", "--headless", "--input", "luxo-hop", "--seconds", "0.1")
    assert "was written for interface 'luxo-mouse', playing it on 'luxo-keys'" in other.stderr


def test_the_no_display_hint_names_a_log_by_name_only_if_the_name_finds_it(tmp_path,
                                                                           monkeypatch):
    """find_log looks in assets/logs/ before recordings/: a recording whose name a
    shipped log also has is given by its path, which replays it, not the other one."""
    import types

    from puppet.app import display, window

    for sub, name in (("assets/logs", "hop"), ("recordings", "hop"), ("recordings", "mine")):
        (tmp_path / sub).mkdir(parents=True, exist_ok=True)
        (tmp_path / sub / f"{name}.jsonl").write_text("{}\n")
    monkeypatch.setattr(catalog, "ROOT", tmp_path)
    monkeypatch.chdir(tmp_path)

    def hint(path):
        return window.headless_hint(types.SimpleNamespace(path=str(path)))

    def says(log):
        return f"(e.g. puppet replay {log} --headless,"

    assert says("hop") in hint(tmp_path / "assets/logs/hop.jsonl")
    assert says("mine") in hint(tmp_path / "recordings/mine.jsonl")
    assert says("mine") in hint("recordings/mine.jsonl")  # (given relative: the same file)
    shadowed = tmp_path / "recordings/hop.jsonl"
    assert says(shadowed) in hint(shadowed), hint(shadowed)
    assert says("recordings/hop.jsonl") in hint("recordings/hop.jsonl")
    elsewhere = tmp_path / "my hop.jsonl"
    assert says(f"'{elsewhere}'") in hint(elsewhere)
    monkeypatch.setattr(display, "os", types.SimpleNamespace(name="nt", environ=os.environ))
    assert says(f'"{elsewhere}"') in hint(elsewhere)  # cmd.exe reads no single quotes
    assert says("hop") in hint(tmp_path / "assets/logs/hop.jsonl")


def test_one_function_cuts_a_long_path_for_every_message(tmp_path, capsys, monkeypatch):
    """catalog.short_path is the one cut of a path too long to show (a name, an output
    file the file system refuses): a catalog name, --screenshot and --export-motion."""
    import puppet.timeline.motion as motion
    from puppet.data.errors import DataError

    monkeypatch.setattr(catalog, "SHORT_PATH", 20)
    import pytest

    with pytest.raises(DataError) as info:
        catalog.find("interface", "n" * 300)
    assert info.value.path == "n" * 17 + "...", info.value.path
    long = tmp_path / ("a" * 300 + ".png")
    code, line = _main_error(capsys, "play", "luxo-mouse", "--headless", "--screenshot",
                             str(long))
    assert (code, line) == (2, f"puppet play: --screenshot {str(long)[:17]}...: File name "
                               f"too long"), line

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(motion, "write_planar_bvh", full)
    out = tmp_path / ("b" * 30 + ".bvh")
    code, line = _main_error(capsys, "replay", "luxo-hop", "--until-step", "10",
                             "--export-motion", str(out))
    assert line == (f"puppet replay: --export-motion {str(out)[:17]}...: cannot write: "
                    f"No space left on device"), line


def _parsers(parser):
    """The parser and every sub-command's parser under it, at any depth."""
    import argparse

    yield parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from _parsers(sub)


def test_no_parser_takes_an_abbreviation(capsys):
    """``--headles`` is a mistake, not ``--headless``: a prefix is never taken for an
    option, in any command (a prefix that fits one option today would quietly mean
    another once a longer one is added)."""
    from puppet.commands import build_parser

    parsers = list(_parsers(build_parser()))
    assert len(parsers) >= 10 and not [p.prog for p in parsers if p.allow_abbrev]
    for argv, line in [
        (("play", "luxo-mouse", "--headles", "--seconds", "0.1"),
         "puppet play: unrecognized arguments: --headles; did you mean '--headless'? "
         "(puppet play --help)"),
        (("replay", "luxo-hop", "--headless", "--chec"),
         "puppet replay: unrecognized arguments: --chec; did you mean '--check'? "
         "(puppet replay --help)"),
        (("mocap", "send", "cmu-131_01-walk", "--spe", "2"),
         "puppet mocap send: unrecognized arguments: --spe 2; did you mean '--speed'? "
         "(puppet mocap send --help)"),
        (("check", "--qui", "luxo"), "puppet check: unrecognized arguments: --qui; did you "
                                     "mean '--quiet'? (puppet check --help)"),
    ]:
        code, got = _main_error(capsys, *argv)
        assert (code, got) == (2, line), argv


def test_a_mistyped_name_gets_a_did_you_mean_in_its_one_line(capsys):
    cases = [
        (("play", "luxo-mous", "--headless"), "puppet play: luxo-mous: no interface named "
                                              "'luxo-mous'; did you mean 'luxo-mouse'? Known: "),
        (("replay", "luxo-hp", "--headless"), "puppet replay: luxo-hp: no log named 'luxo-hp'; "
                                              "did you mean 'luxo-hop'? Known: "),
        (("check", "luxo-mous"), "puppet check: luxo-mous: "),
        (("ply", "luxo-mouse"), "puppet: argument COMMAND: invalid choice: 'ply'; did you "
                                "mean 'play'? (choose from 'play', 'mocap', "),
        (("list", "interfcs"), "puppet list: argument KIND: invalid choice: 'interfcs'; "
                               "did you mean 'interface'? (choose from "),
        (("mocap", "snd"), "puppet mocap: argument WHAT: invalid choice: 'snd'; did you mean "
                           "'send'? (choose from 'info', 'mapping', 'library', 'send', 'listen')"),
    ]
    for argv, start in cases:
        code, line = _main_error(capsys, *argv)
        assert code == 2 and line.startswith(start), (argv, line)
    code, line = _main_error(capsys, "play", "zzzz", "--headless")  # nothing near: no guess
    assert code == 2 and "did you mean" not in line and "no interface named 'zzzz'; known: " \
        in line, line
