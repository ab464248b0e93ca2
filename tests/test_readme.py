"""The README stays a first page, and the docs' links lead somewhere.

The README is at most 200 lines and keeps CI's test command (read by ``.ci/run``); every
relative link of the README and of docs/*.md names a file that exists and, with an
anchor, a heading of that file (GitHub's anchor rules); the README's headless commands
run as written.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
PAGES = [README, *sorted((ROOT / "docs").glob("*.md"))]
LINK = re.compile(r"\]\(([^)\s]+)\)")


def anchor(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to dashes."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    out, fenced = set(), False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (m := re.match(r"^#{1,6} (.*)$", line)):
            out.add(anchor(m.group(1)))
    return out


def test_the_readme_is_a_first_page():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 200
    marker = text.index("<!-- test-command -->\n```sh\n")
    command = text[marker:].split("\n")[2]
    assert command == ("python3 -m venv .venv && .venv/bin/pip install -e '.[test,cluster]' "
                       "&& .venv/bin/python -m pytest -q -n auto --dist loadfile")
    assert "The tests take about" in text
    for page in ("playing", "interfaces", "characters", "mocap", "testing", "benchmarks",
                 "architecture"):
        assert f"(docs/{page}.md)" in text, page


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_link_leads_somewhere(page):
    text = page.read_text(encoding="utf-8")
    bad = []
    for target in LINK.findall(text):
        if re.match(r"^[a-z]+:", target):
            continue  # http(s), mailto: not checked offline
        file, _, frag = target.partition("#")
        dest = (page.parent / file).resolve() if file else page
        if not dest.exists():
            bad.append(f"{target}: no such file")
        elif frag and dest.suffix == ".md" and frag not in anchors(dest):
            bad.append(f"{target}: no heading with that anchor")
    assert not bad, f"{page.name}: " + "; ".join(bad)


def readme_headless_commands() -> list[str]:
    text = README.read_text(encoding="utf-8")
    blocks = re.findall(r"^```sh\n(.*?)^```$", text, re.MULTILINE | re.DOTALL)
    lines = [line.split("  #")[0].strip() for b in blocks for line in b.splitlines()]
    return [c for c in lines if c.startswith("puppet ") and "--headless" in c
            and "*" not in c]  # (the whole check of every log: tests/test_logs.py)


def test_the_readmes_headless_commands_run_as_written(tmp_path, monkeypatch, capsys):
    from puppet.commands import main

    commands = readme_headless_commands()
    assert commands
    monkeypatch.chdir(ROOT)
    for cmd in commands:
        words = [str(tmp_path / w) if w.endswith(".png") else w for w in shlex.split(cmd)]
        assert main(words[1:]) == 0, cmd


def test_the_app_keys_table_of_playing_md_is_puppet_data_keys():
    """docs/playing.md's app key table names every app key of ``APP_KEYS``, and no other
    (the drag, a mouse gesture, is the one row that is not a key)."""
    from puppet.data.keys import APP_KEYS

    text = (ROOT / "docs" / "playing.md").read_text(encoding="utf-8")
    table = text[text.index("| key | app action |"):].split("\n\n")[0].splitlines()[2:]
    said = set()
    for row in table:
        cell = row.split("|")[1].strip().lower().removeprefix("hold ")
        if cell == "`ctrl`+drag":
            continue
        for key in cell.split(" / "):
            key = key.replace("`+`", "+").strip("`")
            said.add({"esc": "escape"}.get(key, key))
    assert said == {chord for chord, _ in APP_KEYS.values()}


def test_playing_md_has_a_row_for_every_shipped_interface():
    """docs/playing.md is where a player looks an interface up: each shipped one has its
    row (`| \\`NAME\\` | ...`), and no row names an interface that is not shipped."""
    text = (ROOT / "docs" / "playing.md").read_text(encoding="utf-8")
    shipped = {p.stem for p in (ROOT / "interfaces").glob("*.yaml")}
    rows = set(re.findall(r"^\| `([a-z0-9-]+)` \|", text, re.M))
    assert shipped - rows == set(), "no row in docs/playing.md"
    named = {r for r in rows if r.startswith(("luxo", "cat", "biped"))}
    assert named - shipped == set(), "rows for interfaces that are not shipped"
