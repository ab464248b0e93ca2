"""The designer docs' examples are valid, and the worked example does what it says.

docs/interfaces.md and docs/scripts.md mark their YAML examples on the first line:
  ``# file: interfaces/NAME.yaml`` / ``# file: assets/scripts/NAME.yaml``  a complete file;
  ``# snippet for luxo``  part of an interface: valid under a three-line Luxo header.
Every marked block must pass ``puppet check``; the worked example's final file
(the last ``interfaces/luxo-hopper.yaml`` block) is also played headless.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from puppet.checker import check_file
from puppet.data.catalog import load_setup
from puppet.session import Session
from puppet.timeline.playback import play
from puppet.timeline.script import compile_script, load_script

DOCS = Path(__file__).resolve().parents[1] / "docs"
DOC_FILES = [DOCS / "interfaces.md", DOCS / "scripts.md"]
FILE_MARK = re.compile(r"# file: (interfaces|assets/scripts)/([A-Za-z0-9_.-]+\.yaml)\s*$")
SNIPPET_MARK = "# snippet for luxo"
LUXO_HEADER = "name: snippet\ndescription: a snippet from the docs\ncharacter: luxo\n"
WORKED = "luxo-hopper.yaml"


def yaml_blocks(path: Path) -> list[tuple[int, str]]:
    """(line number, text) of every ```yaml block; indented blocks (in lists) too."""
    blocks, lines = [], path.read_text(encoding="utf-8").splitlines()
    i = 0
    while i < len(lines):
        m = re.match(r"^(\s*)```yaml\s*$", lines[i])
        if m:
            indent, start, body = len(m.group(1)), i + 1, []
            i += 1
            while not lines[i].strip().startswith("```"):
                body.append(lines[i][indent:])
                i += 1
            blocks.append((start + 1, "\n".join(body) + "\n"))
        i += 1
    return blocks


def marked_blocks():
    out = []
    for doc in DOC_FILES:
        for line, text in yaml_blocks(doc):
            first = text.splitlines()[0]
            if FILE_MARK.match(first) or first.strip() == SNIPPET_MARK:
                out.append(pytest.param(doc.name, line, text, id=f"{doc.name}:{line}"))
    return out


BLOCKS = marked_blocks()


def write_block(tmp_path: Path, line: int, text: str) -> Path:
    first = text.splitlines()[0]
    m = FILE_MARK.match(first)
    if m:  # check_file tells a file's kind by its folder: interfaces/ or scripts/
        folder = tmp_path / ("interfaces" if m.group(1) == "interfaces" else "scripts")
        path = folder / m.group(2)
    else:
        path, text = tmp_path / "interfaces" / f"snippet-{line}.yaml", LUXO_HEADER + text
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def test_docs_have_marked_examples():
    names = [FILE_MARK.match(t.splitlines()[0]) for _, _, t in (p.values for p in BLOCKS)]
    files = {m.group(2) for m in names if m}
    assert WORKED in files and "luxo-hopper-try.yaml" in files
    assert len(BLOCKS) >= 20


@pytest.mark.parametrize("doc, line, text", BLOCKS)
def test_doc_example_is_valid(tmp_path, doc, line, text):
    path = write_block(tmp_path, line, text)
    kind = check_file(path)
    assert kind == ("script" if path.parent.name == "scripts" else "interface")


def worked_example(tmp_path: Path) -> Path:
    """The worked example's final file (the last block of that name), written out."""
    last = [(line, t) for line, t in yaml_blocks(DOCS / "interfaces.md")
            if t.startswith(f"# file: interfaces/{WORKED}")][-1]
    return write_block(tmp_path, *last)


def doc_script(tmp_path: Path, name: str):
    block = [(line, t) for line, t in yaml_blocks(DOCS / "scripts.md")
             if t.startswith(f"# file: assets/scripts/{name}")][-1]
    return load_script(write_block(tmp_path, *block))


def run(session: Session, script, seconds: float, probe, every: float = 1 / 120):
    """Play ``script`` for ``seconds``, calling ``probe(session)`` every ``every`` s."""
    events = compile_script(script, session.sim.dt)
    play(session, events, round(seconds / session.sim.dt),
         max(1, round(every / session.sim.dt)), probe)


def test_worked_example_hops_and_stays_upright(tmp_path):
    session = Session(load_setup(str(worked_example(tmp_path))))
    script = doc_script(tmp_path, "luxo-hopper-short.yaml")  # space at 0.5 s, "1" at 2.5 s
    base = session.character.bodies["base"]
    start_y = base.position.y
    samples = []
    run(session, script, script.seconds,
        lambda s: samples.append((s.time, s.character.in_contact("base"), base.position.y)))
    airborne = [t for t, touching, _ in samples if not touching and t > 0.5]
    assert airborne, "the hop key never lifted the base off the ground"
    assert max(y for _, _, y in samples) > start_y + 0.02
    assert session.character.upright()
    assert session.runtime.state == "upright"
    assert base.position.x > 0.1  # a hop forward


def test_worked_example_script_falls_and_restarts(tmp_path):
    session = Session(load_setup(str(worked_example(tmp_path))))
    script = doc_script(tmp_path, "luxo-hopper-try.yaml")
    seen = {}

    def probe(s):
        t = round(s.time, 3)
        for mark in (2.4, 6.4, 10.5):
            if abs(t - mark) < 1e-6:
                seen[mark] = (s.runtime.state, s.character.upright(),
                              math.degrees(s.character.servos["knee"].target))

    run(session, script, script.seconds, probe, every=0.1)
    assert seen[2.4][:2] == ("upright", True)   # after the hop
    assert seen[6.4][:2] == ("upright", True)   # after the peek
    assert seen[10.5][0] == "fallen"            # pulled over: the 'lie' pose
    assert seen[10.5][2] == pytest.approx(150)
    assert session.runtime.state == "upright"   # space in 'fallen' resets
    assert session.runtime.mode == "keys"
    assert session.character.upright()
    assert abs(session.character.bodies["base"].position.x) < 0.01
