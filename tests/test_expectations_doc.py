"""docs/expectations.md is the reference of every expectation kind, held to the classes
so it cannot drift: one section per registered kind (and none for a kind that does not
exist), each naming every setting of its kind and its margin's unit, with examples
that load as sidecar files; an example marked ``# from: LOG`` is that shipped log's own
(which the log tests replay and pass). The guide and the README point at the page, not
at Python."""

from __future__ import annotations

import re

import msgspec
import pytest
import yaml

from puppet.data.catalog import ROOT
from puppet.data.yamlfile import load_text
from puppet.timeline.expectations import KINDS, validate_expect_file

DOC = ROOT / "docs" / "expectations.md"
TEXT = DOC.read_text(encoding="utf-8")
HEADING = re.compile(r"^### `([a-z_]+)`$", re.MULTILINE)


def _sections() -> dict[str, str]:
    """kind -> its section's text (to the next heading)."""
    marks = list(HEADING.finditer(TEXT))
    out = {}
    for m in marks:
        end = re.compile(r"^#{1,3} [A-Z`]", re.MULTILINE).search(TEXT, m.end())  # a heading
        out[m.group(1)] = TEXT[m.end():end.start() if end else len(TEXT)]
    return out


SECTIONS = _sections()


def _blocks(text: str) -> list[str]:
    return re.findall(r"^```yaml\n(.*?)^```$", text, re.MULTILINE | re.DOTALL)


def _line_of(block: str) -> int:
    return TEXT[:TEXT.index(block)].count("\n") + 1


def test_every_kind_has_one_section_and_every_section_is_a_kind():
    assert sorted(SECTIONS) == sorted(KINDS)
    assert len(HEADING.findall(TEXT)) == len(KINDS)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_kinds_section_names_its_settings_and_its_margin_and_shows_it(kind):
    text, cls = SECTIONS[kind], KINDS[kind]
    for f in msgspec.structs.fields(cls) if cls.written is None else ():  # (a shorthand
        assert f"`{f.encode_name}`" in text, (kind, f.encode_name)    # has no settings)
    said = text.split("Margin:", 1)[1].split(",")[0].split(".")[0].strip()
    if cls.unit:
        assert cls.unit in said.split(" ")[0:3] + said.split(" or "), (kind, said)
    blocks = _blocks(text)
    assert blocks, f"{kind}: no example"
    for block in blocks:
        entries = yaml.safe_load(block)["expect"]
        assert entries and all(list(e) == [kind] for e in entries), (kind, entries)


@pytest.mark.parametrize("block", _blocks(TEXT), ids=_line_of)
def test_every_example_loads_as_a_sidecar_file(block):
    line = _line_of(block)
    spec = validate_expect_file(load_text(block, f"{DOC}:{line}"))
    assert spec.expect
    first = block.splitlines()[0]
    if first.startswith("# from: "):  # the log's own entries (tests/test_logs.py: they pass)
        log = first.removeprefix("# from: ").strip()
        shipped = yaml.safe_load((ROOT / "assets" / "logs" / f"{log}.expect.yaml")
                                 .read_text(encoding="utf-8"))["expect"]
        for entry in yaml.safe_load(block)["expect"]:
            assert entry in shipped, (line, log, entry)


def test_the_guide_and_the_readme_point_at_the_page_not_at_python():
    from tests.test_docs import guide_pages

    guide = "\n".join(p.read_text(encoding="utf-8") for p in guide_pages())
    for name, text in (("the guide", guide),
                       ("README.md", (ROOT / "README.md").read_text(encoding="utf-8"))):
        assert "expectations.py" not in text, name
        assert "expectations.md" in text, name


def test_the_pages_commands_run_as_written(capsys, monkeypatch):
    from puppet.commands import main

    monkeypatch.chdir(ROOT)
    commands = [line.split("#")[0].split() for block in
                re.findall(r"^```sh\n(.*?)^```$", TEXT, re.MULTILINE | re.DOTALL)
                for line in block.splitlines() if line.strip()]
    assert len(commands) == 3
    for words in commands:
        assert words[0] == "puppet"
        assert main(words[1:]) == 0, words
    assert "ok   x_at_end base min 0.5" in capsys.readouterr().out
