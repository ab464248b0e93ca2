"""The YAML loader refuses what could hurt (alias bombs, deep nesting, huge files,
control characters, odd tags) with one line naming file:line:col, and the C parser
(libyaml) and the pure-Python one give the same data, positions and errors."""

import glob
import textwrap
from pathlib import Path

import pytest
import yaml

from puppet.commands.check import check_file
from puppet.data import yamlfile
from puppet.data.errors import DataError

ROOT = Path(__file__).resolve().parents[1]
LOADERS = [pytest.param(yamlfile.PURE_LOADER, id="pure")]
if yamlfile.C_LOADER is not None:
    LOADERS.append(pytest.param(yamlfile.C_LOADER, id="libyaml"))

BAD = {  # text -> (line, col, message fragment; one ending in \n ends the message)
    "bomb": ("a: &a [x, x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a]\n"
             "c: &c [*b, *b, *b, *b, *b, *b, *b, *b]\nd: [*c, *c, *c, *c, *c, *c, *c, *c]\n",
             1, 4, "anchors (&name) and aliases"),
    "alias only": ("a: 1\nb: *a\n", 2, 4, "aliases (*name) are not supported"),
    "deep list": ("a: " + "[" * 1000 + "]" * 1000 + "\n", 1, 51, "nested more than 48"),
    "deep map": ("".join("  " * i + f"k{i}:\n" for i in range(60)), 49, 97, "nested more"),
    "bad float": ("name: x\nmass: !!float abc\n", 2, 7, "'abc' is not a valid float"),
    "bad int": ("a: !!int 0x\n", 1, 4, "is not a valid int"),
    "huge int": ("a: " + "9" * 5000 + "\n", 1, 4, "is not a valid int"),
    "nul": ("a: 1\nb: x\x00y\n", 2, 5, "control character U+0000"),
    "bell": ("a: 1\n\n  b: \x07\n", 3, 6, "control character U+0007"),
    "two documents": ("a: 1\n---\nb: 2\n", 2, 1, "a second YAML document"),
    "merge key": ("a: {x: 1}\nb: {<<: {y: 1}}\n", 2, 5, "tag 'tag:yaml.org,2002:merge'"),
    "python tag": ("a: !!python/name:os.system ''\n", 1, 4, "unsupported YAML value"),
    "set": ("!!set {a, b}\n", 1, 1, "unsupported YAML value"),
    "list key": ("? [a, b]\n: 1\n", 1, 3, "a mapping key must be a plain name"),
    "syntax": ("a: [1, 2\nb: 3\n", 2, 2, "YAML syntax error: the '[' at line 1, column 4 is "
               "not closed by line 2, column 2: expected ',' between its items or ']'"),
    # PyYAML's words for the common mistakes, said plainly (what is wrong, what to do)
    "tab": ("a:\n\t- 1\n", 2, 1, "a tab in the indentation: YAML indents with spaces only"),
    "tab after a dash": ("a:\n  b: [1]\n  c:\n    -\t1\n", 4, 6,
                         "a tab after '-': YAML separates with spaces, not tabs"),
    "one space less": ("a:\n  - name: x\n    shapes:\n      - r: 1\n   mass: 1\n", 5, 4,
                       "'mass' is indented 3 spaces, which lines up with nothing above it: "
                       "YAML nests by indentation, so a line starts in the column of the keys "
                       "it belongs with: expected 4 spaces, like 'shapes' on line 3\n"),
    "one space more": ("a:\n  b: 1\n   c: 2\n", 3, 4,
                       "'c' is indented 3 spaces, more than 'b' on line 2 above it (2 spaces), "
                       "so it reads as the rest of b's value"),
    "item off": ("a:\n  - 1\n - 2\n", 3, 2, "the list item '- 2' is indented 1 space, which "
                 "lines up with nothing above it"),
    "key among items": ("a:\n  - 1\n  b: 2\n", 3, 3, "'b' is a key in the column of the list "
                        "items above (the '-' on line 2): a list holds '- ' items only"),
    "item among keys": ("a:\n  b: 2\n  - 1\n", 3, 3, "the list item '- 1' is in the column of "
                        "the keys above ('b' on line 2): a mapping holds 'key: value' lines"),
    "no colon": ("a: 1\nb 2\nc: 3\n", 2, 1, "'b 2' is not 'key: value': expected a ':' and a "
                 "space after the key"),
    "no colon, runs on": ("a:\n  - name x\n    mass: 1\n", 2, 5, "'name x' is not 'key: value': "
                          "expected a ':' and a space after the key, so it runs on into line 3"),
    "no space after colon": ("maps:\n  - input:mouse.x\n    joint: ankle\n", 2, 5,
                             "'input:mouse.x' is not 'key: value': expected a ':' and a space "
                             "after the key; a ':' right before other text is part of the "
                             "text, so it runs on into line 3"),
    "no space, a comment": ("maps:\n  - input:mouse.x  # x\n    joint: ankle\n", 2, 5,
                             "'input:mouse.x' is not 'key: value': expected a ':' and a space "
                             "after the key; a ':' right before other text is part of the "
                             "text, so 'joint' on line 3 cannot go with it"),
    "runs on from an item": ("a:\n  - 0.2\n   over: 0.1\n", 3, 4,
                             "'over' reads as the rest of the value '0.2' on line 2"),
    "item after a key": ("a: 1\nevents: - {t: 0}\n", 2, 9, "a list item ('- ') after "
                         "'events:' on the same line: a list's items start lines of their own"),
    "no key": ("a:\n  b: 1\n  : 2\n", 3, 3, "a ':' with no key before it"),
    "first line indented": (" a: 1\nb: 2\n", 2, 1, "'b' is indented 0 spaces, less than the "
                            "file's first line ('a' on line 1, 1 space)"),
    "first line indented, named": ("# c\n  name: x\n  mass: 1\n description: y\n", 4, 2,
                                   "less than the file's first line ('name' on line 2, 2 "
                                   "spaces)"),
    "colon no space": ("a:\n  b:1\n  c: 2\n", 2, 3, "'b:1' is not 'key: value'"),
    "colon in value": ("name: luxo: lamp\n", 1, 11, "the value of 'name' holds ': ' "
                       "('luxo: lamp'): quote the whole value (name: \"luxo: lamp\")"),
    "unclosed quote": ("a: 1\nb: 'x\nc: 3\n", 2, 4, "the quote (') that starts here is never "
                       "closed"),
    "text after quote": ("a: 'it's'\n", 1, 8, "text after the closing quote (') of a value"),
    "escape": ('a: "C:\\path"\n', 1, 7, "'\\p' is not an escape in a double-quoted value"),
    "extra bracket": ("a: [1, 2]]\n", 1, 10, "a ']' with no '[' open before it"),
    "two commas": ("a: [1, , 2]\n", 1, 8, "two commas with no item between them"),
    "reserved": ("a: @x\n", 1, 4, "'@' cannot start an unquoted value"),
    "crlf": ("a:\r\n  b: 1\r\n c: 2\r\n", 3, 2, "'c' is indented 1 space, which lines up"),
    # a reviewer's findings: messages whose fix would not have worked
    "colon in a { } value": ("maps:\n  - {input: mouse.x, description: mouse x: the thigh}\n",
                             2, 42, "the value of 'description' holds ': ' ('mouse x: the "
                             "thigh'): quote the whole value (description: \"mouse x: the "
                             "thigh\")"),
    "{ } missing comma": ("maps:\n  - {input: mouse.x joint: ankle}\n", 2, 26,
                          "(input: \"mouse.x joint: ankle\"); or, if 'joint' starts the next "
                          "item, put a ',' before it"),
    "colon, backslash": ("name: x\ndescription: C:\\Users\\x: y\n", 2, 24,
                         "quote the whole value (description: 'C:\\Users\\x: y')"),
    "colon, double quotes": ('name: x\ndescription: say "hi": there\n', 2, 22,
                             "quote the whole value (description: 'say \"hi\": there')"),
    "colon, both quotes": ("name: x\ndescription: it's \"x\": odd\n", 2, 22,
                           "(description: 'it''s \"x\": odd')"),
    "colon, a comment": ("name: x\ndescription: hop: forward  # n\n", 2, 17,
                         "(description: \"hop: forward\"), or"),
    "colon, long value": ("name: x\ndescription: " + "a" * 40 + ": " + "b" * 40 + "\n", 2, 54,
                          '(description: "' + "a" * 32 + " ... " + "b" * 10 + '"), or'),
    "\\U escape": ('name: x\ndescription: "C:\\Users\\me"\n', 2, 17,
                   "'\\U' in a double-quoted value starts an escape of 8 hexadecimal digits "
                   "(a character code), and '\\Us' is not one: write '\\\\' for a backslash, "
                   "or quote the value with ' ' instead ('C:\\Users\\me')"),
    "\\x escape": ('maps:\n  - {input: a, description: "C:\\xyz"}\n', 2, 32,
                   "'\\x' in a double-quoted value starts an escape of 2 hexadecimal digits"),
    "after a block of text": ("name: x\nnotes: |\n  some text\n\n  more text\n bad: 1\n", 6, 2,
                              "'bad' is indented 1 space: more than 'notes' on line 2 above it "
                              "(0 spaces), less than the lines of its block of text ('|' or "
                              "'>'), which ends at the first line indented less than them: "
                              "YAML nests by indentation, so a line starts in the column of "
                              "the keys it belongs with: expected 0 spaces, like 'notes' on "
                              "line 2\n"),
    "under a { } item": ("maps:\n  - {input: mouse.x,\n     joint: ankle}\n   bad: 1\n", 4, 4,
                         "'bad' is indented under the '{ }' on line 2: a value written in "
                         "'{ }' holds its keys inside it, separated by ',' (add 'bad: 1' "
                         "before its closing '}')"),
    "after a - | item": ("poses:\n  - |\n    hello\n   bad: 1\n", 4, 4,
                         "block of text ('|' or '>'), which ends at the first line indented "
                         "less than them: YAML nests by indentation, so a line starts in the "
                         "column of the keys it belongs with: expected 0 spaces, like 'poses' "
                         "on line 1\n"),
    "dash, no space": ("maps:\n  -input: mouse.x\n   joint: ankle\n", 2, 3,
                       "'-input: mouse.x' starts with '-' but no space after it, so it is not "
                       "a list item: a list item's '-' needs a space after it ('- input: "
                       "mouse.x')"),
    "dash, no space, among items": ("maps:\n  - input: mouse.x\n  -joint: ankle\n", 3, 3,
                                    "'-joint: ankle' starts with '-' but no space after it"),
    "dash, no space, first item": ("poses:\n  -name: stand\n  - name: sit\n", 2, 3,
                                   "a list item's '-' needs a space after it ('- name: stand')"),
    "a key is not offered a '-' column": ("a:\n  - name: x\n    b: 1\n   c: 2\n", 4, 4,
                                          "expected 4 spaces, like 'b' on line 3\n"),
    "a key is offered the keys' columns": ("a:\n  b:\n    c: 1\n   d: 2\n", 4, 4,
                                           "expected 4 spaces, like 'c' on line 3, or 2, "
                                           "like 'b' on line 2\n"),
}


@pytest.mark.parametrize("loader", LOADERS)
@pytest.mark.parametrize("name", BAD)
def test_bad_yaml_is_one_line_with_position(name, loader):
    text, line, col, fragment = BAD[name]
    with pytest.raises(DataError) as info:
        yamlfile.load_text(text, "f.yaml", loader)
    err = info.value
    assert (err.line, err.col) == (line, col), str(err)
    assert fragment in err.message + "\n" and "\n" not in str(err), str(err)


def test_both_loaders_give_the_same_errors_for_every_broken_example(monkeypatch):
    if yamlfile.C_LOADER is None:
        pytest.skip("PyYAML without libyaml: only the pure-Python loader exists")
    for path in sorted((ROOT / "tests" / "broken").glob("*.yaml")):
        found = []
        for loader in (yamlfile.C_LOADER, yamlfile.PURE_LOADER):
            monkeypatch.setattr(yamlfile, "C_LOADER", loader)
            with pytest.raises(DataError) as info:
                check_file(path)
            found.append(str(info.value))
        assert found[0] == found[1], path


def test_both_loaders_read_the_shipped_files_alike():
    if yamlfile.C_LOADER is None:
        pytest.skip("PyYAML without libyaml")
    files = [p for pattern in ("characters/*.yaml", "interfaces/*.yaml", "assets/*/*.yaml")
             for p in glob.glob(str(ROOT / pattern))]
    assert len(files) > 20
    for path in files:
        text = Path(path).read_text(encoding="utf-8")
        a = yamlfile.load_text(text, path, yamlfile.C_LOADER)
        b = yamlfile.load_text(text, path, yamlfile.PURE_LOADER)
        assert (a.data, a.value_pos, a.key_pos) == (b.data, b.value_pos, b.key_pos), path


def test_the_c_parser_is_used_when_pyyaml_has_it():
    assert (yamlfile.C_LOADER is not None) == bool(yaml.__with_libyaml__)


def test_forcing_the_pure_python_loader(monkeypatch):
    """With no C loader (PyYAML built without libyaml) every check still works."""
    monkeypatch.setattr(yamlfile, "C_LOADER", None)
    calls = []
    real = yamlfile._parse
    monkeypatch.setattr(yamlfile, "_parse",
                        lambda text, path, cls: calls.append(cls) or real(text, path, cls))
    check_file(ROOT / "interfaces" / "luxo-keys.yaml")
    assert calls and set(calls) == {yamlfile.PURE_LOADER}  # interface and character
    with pytest.raises(DataError, match=r"char-yaml-syntax.yaml:7:5: YAML syntax error"):
        check_file(ROOT / "tests" / "broken" / "char-yaml-syntax.yaml")


def test_file_size_is_capped_before_reading_it_all(tmp_path, monkeypatch):
    monkeypatch.setattr(yamlfile, "MAX_BYTES", 1000)
    big = tmp_path / "big.yaml"
    big.write_text("a: '" + "x" * 2000 + "'\n")
    with pytest.raises(DataError, match=r"big.yaml: file too large .*at most 1000 bytes"):
        yamlfile.load_file(big)
    with pytest.raises(DataError, match="file too large"):
        yamlfile.load_text("a: '" + "\u00e9" * 600 + "'\n", "t.yaml")  # 1200 bytes


def test_not_utf8_names_its_line(tmp_path):
    bad = tmp_path / "latin1.yaml"
    bad.write_bytes(b"name: x\ndescription: caf\xe9\n")
    with pytest.raises(DataError, match=r"latin1.yaml:2:17: not UTF-8 text"):
        yamlfile.load_file(bad)


def test_a_directory_is_refused_in_one_line(tmp_path):
    with pytest.raises(DataError, match="is a directory"):
        yamlfile.load_file(tmp_path)


# -- numbers: finite, in documented ranges ------------------------------------------
def test_the_ranges_doc_lists_every_range_as_the_code_has_it():
    from puppet.data.ranges import RANGES, describe

    text = (ROOT / "docs" / "ranges.md").read_text(encoding="utf-8")
    table = text.split("<!-- ranges-table -->", 1)[1]
    rows = {line.split("|")[1].strip(): line.split("|")[2].strip()
            for line in table.splitlines() if line.startswith("| ") and "---" not in line}
    rows.pop("range")
    assert rows == {name: describe(name) for name in RANGES}


CHAR = """\
name: x
description: y
links:
  - name: base
    mass: {mass}
    shapes: [{{type: circle, radius: {radius}}}]
  - name: arm
    mass: 0.1
    shapes: [{{type: box, size: [0.1, 0.02], center: [{cx}, 0]}}]
joints:
  - {{name: j, parent: base, child: arm, anchor: [0, 0], pd: {{stiffness: {k}, damping: 1, max_torque: 5}}}}
start: {{angle: {angle}, joints: {{j: 0}}}}
"""  # noqa: E501 - one joint a line: the cases name their line numbers
GOOD = dict(mass=1, radius=0.1, cx=0.1, k=10, angle=0)


@pytest.mark.parametrize("field,value,line,fragment", [
    ("mass", ".nan", 5, "'links.0.mass': must be a finite number in 0.001..1000 kg (got nan)"),
    ("mass", "-1", 5, "0.001..1000 kg"),
    ("mass", "1.0e+308", 5, "0.001..1000 kg"),
    ("radius", ".inf", 6, "'links.0.shapes.0.radius': must be a finite number in 0.001..10 m"),
    ("cx", "-.inf", 9, "-10..10 m"),
    ("k", "1.0e+12", 11, "0..1e6 N*m/rad"),
    ("angle", ".nan", 12, "-360..360 deg"),
    ("angle", "true", 12, "expected a number"),
])
def test_character_numbers_are_finite_and_in_range(tmp_path, field, value, line, fragment):
    path = tmp_path / "c.yaml"
    path.write_text(CHAR.format(**{**GOOD, field: value}))
    with pytest.raises(DataError) as info:
        check_file(path)
    assert info.value.line == line and fragment in info.value.message, str(info.value)


def test_the_good_character_of_these_tests_is_accepted(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text(CHAR.format(**GOOD))
    check_file(path)


@pytest.mark.parametrize("text,fragment", [
    ("name: s\ndescription: d\ngravity: [0, -.inf]\nground: [{points: [[0, 0], [1, 0]]}]\n",
     "3:14: bad value for 'gravity.1': must be a finite number in -1000..1000 m/s^2"),
    ("name: s\ndescription: d\nground: [{points: [[0, 0], [1.0e+300, 0]]}]\n",
     "3:29: bad value for 'ground.0.points.1.0': must be a finite number in -10000..10000 m"),
    ("name: s\ndescription: d\nground: [{points: [[0, 0], [1, 0]], color: [300, 0, 0]}]\n",
     "each a whole number 0..255"),
    ("events:\n  - {t: .inf, key: a}\n", "2:9: bad value for 'events.0.t': must be a finite "
                                        "number in 0..3600 s (got inf)"),
    ("events:\n  - {t: 1, mouse: [0.5, 0.5], over: 1.0e+9}\n", "0..600 s"),
    ("events:\n  - {t: 1, drag: {link: base, to: [.nan, 0]}}\n", "-10000..10000 m"),
    ("name: i\ndescription: d\ncharacter: luxo\nkeys:\n  - {key: g, gravity: [0, 1.0e+8]}\n",
     "5:27: bad value for 'keys.0.gravity.1': must be a finite number in -1000..1000"),
    ("name: i\ndescription: d\ncharacter: luxo\nkeys:\n  - {key: g, adjust: {ankle: .nan}}\n",
     "-720..720 deg"),
    ("name: i\ndescription: d\ncharacter: luxo\nperturbation: {every: 0}\n",
     "0.001..3600 s"),
    ("name: i\ndescription: d\ncharacter: luxo\ngains: {ankle: {max_torque: .inf}}\n",
     "0..1e6 N*m, more than 0"),
])
def test_scene_script_interface_numbers_are_finite_and_in_range(tmp_path, text, fragment):
    kind = "script" if text.startswith("events") else "scene" if "ground" in text else "iface"
    folder = {"script": "assets/scripts", "scene": "assets/scenes", "iface": "interfaces"}[kind]
    path = tmp_path / folder / "x.yaml"
    path.parent.mkdir(parents=True)
    path.write_text(text)
    with pytest.raises(DataError) as info:
        check_file(path)  # the folder tells the kind
    assert fragment in str(info.value) and "\n" not in str(info.value), str(info.value)


@pytest.mark.parametrize("mass", ["-0.5", "0"])
def test_puppet_check_refuses_a_character_with_a_mass_not_above_zero(tmp_path, capsys, mass):
    from puppet.commands import main

    path = tmp_path / "c.yaml"
    path.write_text(textwrap.dedent(f"""\
        name: x
        description: y
        links:
          - name: base
            mass: 1
            shapes: [{{type: circle, radius: 0.1}}]
          - name: arm
            mass: {mass}
            shapes: [{{type: box, size: [0.1, 0.02], center: [0.1, 0]}}]
        joints:
          - {{name: j, parent: base, child: arm, anchor: [0, 0],
              pd: {{stiffness: 10, damping: 1, max_torque: 5}}}}
        start: {{angle: 0, joints: {{j: 0}}}}
        """))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f" {path}:8:11: bad value" in err[0], err
    assert "links.1.mass" in err[0] and "kg" in err[0]
