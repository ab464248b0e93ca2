"""The YAML loader refuses what could hurt (alias bombs, deep nesting, huge files,
control characters, odd tags) with one line naming file:line:col, and the C parser
(libyaml) and the pure-Python one give the same data, positions and errors."""

import glob
from pathlib import Path

import pytest
import yaml

from puppet.checker import check_file
from puppet.data import yamlfile
from puppet.data.errors import DataError

ROOT = Path(__file__).resolve().parents[1]
LOADERS = [pytest.param(yamlfile.PURE_LOADER, id="pure")]
if yamlfile.C_LOADER is not None:
    LOADERS.append(pytest.param(yamlfile.C_LOADER, id="libyaml"))

BAD = {  # text -> (line, col, message fragment)
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
    "syntax": ("a: [1, 2\nb: 3\n", 2, 2, "YAML syntax error: expected ',' or ']'"),
    "tab": ("a:\n\t- 1\n", 2, 1, "found character '\\t' that cannot start any token"),
}


@pytest.mark.parametrize("loader", LOADERS)
@pytest.mark.parametrize("name", BAD)
def test_bad_yaml_is_one_line_with_position(name, loader):
    text, line, col, fragment = BAD[name]
    with pytest.raises(DataError) as info:
        yamlfile.load_text(text, "f.yaml", loader)
    err = info.value
    assert (err.line, err.col) == (line, col), str(err)
    assert fragment in err.message and "\n" not in str(err), str(err)


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
"""
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
