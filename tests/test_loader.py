"""Malformed data files are refused with one line naming file:line and what was wrong.

Each file under tests/broken/ says on its first line what must be reported:
``# expect: LINE: message fragment``.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from puppet.commands.check import check_file
from puppet.data.errors import DataError

BROKEN = sorted((Path(__file__).parent / "broken").glob("*.yaml"))


def expectation(path: Path) -> tuple[int, str]:
    first = path.read_text().splitlines()[0]
    match = re.match(r"# expect: (\d+): (.*)", first)
    assert match, f"{path} must start with '# expect: LINE: message'"
    return int(match.group(1)), match.group(2)


@pytest.mark.parametrize("path", BROKEN, ids=[p.stem for p in BROKEN])
def test_broken_file_is_rejected_with_file_and_line(path):
    line, fragment = expectation(path)
    with pytest.raises(DataError) as info:
        check_file(path)
    err = info.value
    assert err.path == str(path)
    assert err.line == line, str(err)
    assert fragment in err.message, str(err)
    assert "\n" not in str(err)
    # the words are puppet's, never the validation library's
    assert not re.search(r"Input (should|tag)|found using|validation error|pydantic|"
                         r"Value error|after validation|msgspec|Expected `|Object (contains|"
                         r"missing)|Invalid (enum )?value|- at `", str(err)), str(err)


def test_every_kind_of_file_has_broken_examples():
    kinds = {p.stem.split("-")[0] for p in BROKEN}
    assert {"char", "scene", "iface", "script"} <= kinds


def test_cli_reports_one_line_and_exit_code_2():
    path = Path(__file__).parent / "broken" / "char-unknown-key.yaml"
    proc = subprocess.run([sys.executable, "-m", "puppet", "check", str(path)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"puppet check: {path}:9:5: unknown key 'mas'")
    assert "Traceback" not in proc.stderr


def test_play_refuses_invalid_interface_without_traceback(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: bad\ndescription: x\ncharacter: luxo\nmaps:\n"
                   "  - {input: mouse.x, joint: ankle, to: [0, 'far']}\n")
    proc = subprocess.run([sys.executable, "-m", "puppet", "play", str(bad), "--headless",
                           "--seconds", "0.1"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and f"{bad}:5:" in proc.stderr, proc.stderr
    assert "Traceback" not in proc.stderr


def test_yaml_never_runs_code(tmp_path):
    marker = tmp_path / "owned"
    bad = tmp_path / "evil.yaml"
    bad.write_text(f"name: x\ndescription: !!python/object/apply:os.system "
                   f"['touch {marker}']\nlinks: []\n")
    with pytest.raises(DataError):
        check_file(bad)
    assert not marker.exists()


def test_a_bad_recorded_gesture_is_refused_in_puppets_words():
    """with_gesture (F2 records, F3 saves) validates the path as a file's would be."""
    from puppet.data.interfaces import load_interface, with_gesture

    spec, _ = load_interface(Path(__file__).parent.parent / "interfaces" / "luxo-mouse.yaml")
    cases = {(): "bad value for 'path': expected at least 1 item(s)",
             ((0.0, 0.5, float("nan")),): "bad value for 'path.0.2': must be a finite number",
             ((0.0, 0.5),): "bad value for 'path.0': expected 3 items, got 2"}
    for path, fragment in cases.items():
        with pytest.raises(ValueError) as info:
            with_gesture(spec, "g", list(path))
        assert str(info.value).startswith("bad gesture: ") and fragment in str(info.value)
    ok = with_gesture(spec, "g", [(0, 0.2, 0.3), (0.1, 0.4, 0.5)])
    assert ok.gestures[-1].path == [(0.0, 0.2, 0.3), (0.1, 0.4, 0.5)]
    assert all(type(v) is float for v in ok.gestures[-1].path[0])


def test_what_was_accepted_before_still_is(tmp_path):
    """Conversion is lax as pydantic's was: 20.0 for a whole number, a number written as
    text, 1 for true; the values come out of the types the fields say."""
    import re as _re

    from puppet.data.characters import load_character

    text = (Path(__file__).parent.parent / "characters" / "luxo.yaml").read_text()
    text = _re.sub(r"mass: ([0-9.]+)", r"mass: '\1'", text, count=1)
    path = tmp_path / "characters" / "lax.yaml"
    path.parent.mkdir()
    path.write_text(text.replace("\nlinks:", "\nsolver: {iterations: 20.0}\nlinks:", 1))
    spec = load_character(path)
    assert spec.solver.iterations == 20 and type(spec.solver.iterations) is int
    assert type(spec.links[0].mass) is float and spec.links[0].mass > 0
    path.write_text(text.replace("\nlinks:", "\nsolver: {iterations: true}\nlinks:", 1))
    with pytest.raises(DataError, match="expected a whole number"):
        load_character(path)


@pytest.mark.parametrize("value, said", [
    ("1" + "0" * 400, "must be a finite number in 0.001..1000 kg"),  # past any float
    ("'-1'", "must be a finite number in 0.001..1000 kg (got '-1')"),  # text, out of range
    ("'1e400'", "must be a finite number in 0.001..1000 kg (got '1e400')"),
    ("'heavy'", "expected a number"),
])
def test_a_number_past_any_float_or_written_as_text_is_a_one_line_range_error(
        tmp_path, value, said):
    from puppet.data.characters import load_character

    text = (Path(__file__).parent.parent / "characters" / "luxo.yaml").read_text()
    path = tmp_path / "characters" / "odd.yaml"
    path.parent.mkdir()
    path.write_text(re.sub(r"mass: [0-9.]+", "mass: " + value, text, count=1))
    with pytest.raises(DataError) as caught:
        load_character(path)
    message = str(caught.value)
    assert said in message and "links.0.mass" in message and "\n" not in message


@pytest.mark.parametrize("file, old, new, said", [
    ("biped-auto", "hold: parent}", "hold: 0}", "expected one of: child, parent (got 0)"),
    ("biped-auto", "hold: parent}", "hold: mom}", "expected one of: child, parent (got 'mom')"),
    ("luxo-keys", "sequence: small_hop,", "sequence: small_hop, repeat: always,",
     "expected one of: forever, or a whole number (got 'always')"),
])
def test_a_word_not_among_the_choices_names_the_choices_and_the_unions_other_kinds(
        tmp_path, file, old, new, said):
    from puppet.data.interfaces import load_interface

    text = (Path(__file__).parent.parent / "interfaces" / f"{file}.yaml").read_text()
    assert old in text
    path = tmp_path / "interfaces" / f"{file}.yaml"
    path.parent.mkdir()
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(DataError) as caught:
        load_interface(path)
    assert said in str(caught.value)


@pytest.mark.parametrize("key", ["a` - at `$.ground[0]", "a` - at `key` in `$.start",
                                 "Object missing required field `name`"])
def test_a_key_that_reads_like_a_path_is_reported_as_itself_where_it_is(tmp_path, key):
    """The validator's message is text with the path at its end; a key holding the same
    words must not move the error to another line or name another key."""
    from puppet.data.scenes import load_scene

    text = (Path(__file__).parent.parent / "assets" / "scenes" / "flat.yaml").read_text()
    path = tmp_path / "scenes" / "odd.yaml"
    path.parent.mkdir()
    path.write_text(text.rstrip("\n") + "\n" + yaml_quoted(key) + ": 1\n")
    line = len(path.read_text().splitlines())
    with pytest.raises(DataError) as caught:
        load_scene(path)
    message = str(caught.value)
    assert f"odd.yaml:{line}:1: unknown key '{key}'" in message, message


def yaml_quoted(text: str) -> str:
    """``text`` as a double-quoted YAML scalar."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def test_a_number_for_text_is_quoted_as_written_not_as_read():
    """The hint quotes the source text at the value's place (``0x1F``, not 31), from a
    text read in memory (a reload event's) as from a file; without a text (data built
    in code) it can only say the value."""
    from puppet.data.interfaces import parse_interface
    from puppet.data.validate import located_data
    from puppet.data.yamlfile import load_text

    def message(text):
        with pytest.raises(DataError) as info:
            parse_interface(load_text(text, "in-memory.yaml"))
        return info.value

    head = "name: x\ndescription: d\ncharacter: luxo\nkeys:\n"
    cases = [("  - {key: 0x1F, set: {ankle: 10}}\n", "'0x1F'", "a number", 31),
             ("  - {set: {ankle: 10},\n     key: 1_0}\n", "'1_0'", "a number", 10),
             ("  - {key: 0o7, set: {ankle: 10}}\n", None, "", 0),  # text: not this hint
             ("  - key: Off # lights\n    set: {ankle: 10}\n", "'Off'", "false", False),
             ("  - key: +1.50\n    set: {ankle: 10}\n", "'+1.50'", "a number", 1.5)]
    for keys, written, reads, got in cases:
        err = message(head + keys)
        if written is None:
            assert "in quotes" not in err.message, err
            continue
        assert err.message.endswith(f"expected text in quotes, {written} (unquoted, YAML "
                                    f"reads it as {reads}) (got {got!r})"), err
    err = message("name: x\ndescription: 12:30:00\ncharacter: luxo\n")  # base 60
    assert "in quotes, '12:30:00' (unquoted, YAML reads it as a number) (got 45000)" \
        in err.message, err
    data = {"name": "x", "description": "d", "character": "luxo",
            "keys": [{"key": 31, "set": {"ankle": 10}}]}
    with pytest.raises(DataError) as info:
        parse_interface(located_data(data, "code"))
    assert "expected text in quotes, '31' (unquoted" in info.value.message
