"""The designer docs' examples are valid, and the worked example does what it says.

The guide (docs/interfaces.md and its chapters) and docs/scripts.md mark their YAML
examples on the first line:
  ``# file: interfaces/NAME.yaml`` / ``# file: assets/scripts/NAME.yaml`` /
  ``# file: assets/scenes/NAME.yaml``  a complete file;
  ``# snippet for luxo``  part of an interface: valid under a three-line header naming
                          that character (luxo, cat, biped...).
Every marked block must pass ``puppet check``; the worked example's final file
(the last ``interfaces/luxo-hopper.yaml`` block) is also played headless.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from puppet.commands.check import check_file
from puppet.data.catalog import load_setup
from puppet.interface import events as ev
from puppet.session import Session
from puppet.session.playback import play
from puppet.timeline.script import compile_script, load_script

DOCS = Path(__file__).resolve().parents[1] / "docs"

def guide_pages() -> list[Path]:
    """The designer's guide: its front page, then its chapters (docs/interfaces/)."""
    return [DOCS / "interfaces.md", *sorted((DOCS / "interfaces").glob("*.md"))]


DOC_FILES = [*guide_pages(), DOCS / "scripts.md"]
FILE_MARK = re.compile(r"# file: (interfaces|assets/scripts|assets/scenes|assets/mappings)/"
                       r"([A-Za-z0-9_.-]+\.yaml)\s*$")
SNIPPET_MARK = "# snippet for luxo"
SNIPPET = re.compile(r"# snippet for ([a-z0-9-]+)\s*$")


def snippet_header(character: str) -> str:
    return f"name: snippet\ndescription: a snippet from the docs\ncharacter: {character}\n"
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


def guide_blocks() -> list[tuple[int, str]]:
    """Every ```yaml block of the guide's pages, in reading order."""
    return [block for page in guide_pages() for block in yaml_blocks(page)]


def marked_blocks():
    out = []
    for doc in DOC_FILES:
        for line, text in yaml_blocks(doc):
            first = text.splitlines()[0]
            if FILE_MARK.match(first) or SNIPPET.match(first.strip()):
                out.append(pytest.param(doc.name, line, text, id=f"{doc.name}:{line}"))
    return out


BLOCKS = marked_blocks()


def write_block(tmp_path: Path, line: int, text: str) -> Path:
    first = text.splitlines()[0]
    m = FILE_MARK.match(first)
    if m:  # check_file tells a file's kind by its folder: interfaces/, scripts/, scenes/
        path = tmp_path / m.group(1).split("/")[-1] / m.group(2)
    else:
        character = SNIPPET.match(first.strip()).group(1)
        path = tmp_path / "interfaces" / f"snippet-{line}.yaml"
        text = snippet_header(character) + text
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
    assert kind == {"scripts": "script", "scenes": "scene",
                    "mappings": "mapping"}.get(path.parent.name, "interface")


def worked_example(tmp_path: Path) -> Path:
    """The worked example's final file (the last block of that name), written out."""
    last = [(line, t) for line, t in guide_blocks()
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


# -- the guide's examples of chains, props, steering, machines, repeat, channels ---------
def doc_session(tmp_path: Path, contains: str) -> Session:
    """A session of the one marked block of docs/interfaces.md containing ``contains``."""
    found = [(line, t) for line, t in guide_blocks()
             if contains in t and (FILE_MARK.match(t.splitlines()[0])
                                   or SNIPPET.match(t.splitlines()[0].strip()))]
    assert len(found) == 1, f"{len(found)} blocks contain {contains!r}"
    return Session(load_setup(str(write_block(tmp_path, *found[0]))))


def tap(session: Session, key: str) -> None:
    session.handle(ev.key(key, True))
    session.handle(ev.key(key, False))


def test_guide_repeat_plays_three_times_and_forever_until_a_pose(tmp_path):
    s = doc_session(tmp_path, "sequence: nod, repeat: 3")
    tap(s, "n")
    s.advance(round(0.59 * 480))
    assert s.runtime.sequence is not None
    s.advance(round(0.02 * 480))
    assert s.runtime.sequence is None  # 0.6 s: three plays of 0.2 s
    tap(s, "m")
    s.advance(5 * 480)
    assert s.runtime.sequence is not None  # forever
    tap(s, "1")
    s.advance(50)
    assert s.runtime.sequence is None


def test_guide_goto_to_the_current_state_runs_its_entry_again(tmp_path):
    s = doc_session(tmp_path, "goto: nodding, description: lean 5 degrees more")
    ankle = s.character.servos["ankle"]
    assert math.degrees(ankle.target) == pytest.approx(-30)  # the start's -25, then -5
    s.advance(240)
    tap(s, "a")
    assert math.degrees(ankle.target) == pytest.approx(-35)
    s.advance(400)  # 1 s after the start, not after the press: still nodding
    assert s.runtime.state == "nodding"
    s.advance(100)
    assert s.runtime.state == "resting" and math.degrees(ankle.target) == pytest.approx(-25)


def test_guide_two_machines_run_side_by_side(tmp_path):
    s = doc_session(tmp_path, "goto: main.waiting")
    assert s.runtime.states == {"main": "waiting", "watch": "open"}
    tap(s, "k")  # fold the knee
    s.advance(250)
    assert s.runtime.states == {"main": "ticking", "watch": "folded"}
    assert s.character.servos["ankle"].stiffness == 25
    tap(s, "space")  # watch's key moves main
    assert s.runtime.states == {"main": "waiting", "watch": "folded"}


def test_guide_prop_reaches_walk_along_the_rail(tmp_path):
    s = doc_session(tmp_path, "point: {prop: rail, offset: 1}")
    s.advance(240)
    rail = s.sim.props["rail"]
    shade = s.runtime.chains["shade"]
    for key, want in (("e", "back"), ("n", "middle"), ("n", "front"), ("n", "front"),
                      ("v", "middle")):
        tap(s, key)
        s.advance(400)
        assert math.dist(shade.end_world(s.character), rail.point_world(want)) < 0.01, key
    tap(s, "g")  # catch the swing
    s.advance(480)
    assert "shade" in s.runtime.grasped
    tap(s, "u")
    s.advance(10)
    assert s.runtime.grasped == {}


def test_guide_steered_reach_follows_the_mouse_and_the_hand_channels(tmp_path):
    s = doc_session(tmp_path, "steer: {x: channel.hand_x")
    s.advance(240)
    base = s.character.bodies["base"]
    shade = s.runtime.chains["shade"]
    tap(s, "t")
    s.handle(ev.mouse(1.0, 0.0))  # right and down: the box's corner [0.06, 0.32]
    s.advance(240)
    assert math.dist(shade.end_world(s.character), base.local_to_world((0.06, 0.32))) < 0.01
    tap(s, "y")
    s.handle(ev.channels({"hand_x": -1.0, "hand_y": 1.0}))  # the other corner
    s.advance(480)  # the base rocks as the shade swings over, and the box with it
    assert math.dist(shade.end_world(s.character), base.local_to_world((-0.04, 0.40))) < 0.01
    tap(s, "1")
    s.advance(2)
    assert s.runtime.reaches == {}


def test_guide_channels_drive_their_maps(tmp_path):
    s = doc_session(tmp_path, "input: channel.lean")
    before = {n: sv.target for n, sv in s.character.servos.items()}
    s.handle(ev.channels({"fold": 0.5}))  # lean not sent yet: the ankle stays
    s.runtime.flush()  # a frame's maps act when anything next happens (here: now)
    assert s.character.servos["ankle"].target == before["ankle"]
    assert math.degrees(s.character.servos["knee"].target) == pytest.approx(70)
    s.handle(ev.channels({"lean": 2.0, "fold": 0.0}))  # beyond 'from': the end
    s.runtime.flush()
    assert math.degrees(s.character.servos["ankle"].target) == pytest.approx(60)
    assert math.degrees(s.character.servos["knee"].target) == pytest.approx(0)


def test_guide_cat_paw_reaches_with_three_joints_and_the_spine_stops_at_its_limit(tmp_path):
    s = doc_session(tmp_path, "name: cat-paw")
    s.advance(240)
    hips = s.character.bodies["hips"]
    target = hips.local_to_world((0.18, 0.12))
    paw = s.runtime.chains["paw"]
    start = math.dist(paw.end_world(s.character), target)
    tap(s, "e")
    s.advance(480)
    assert math.dist(paw.end_world(s.character), target) < 0.3 * start
    spine = s.character.servos["spine"]
    assert math.degrees(spine.target) == pytest.approx(35, abs=0.5)  # at its limit
    assert s.character.upright()


def test_guide_roles_example_swaps_which_leg_the_mouse_drives(tmp_path):
    s = doc_session(tmp_path, "name: roles-example")
    servos = s.character.servos
    s.handle(ev.mouse(1.0, 0.5))
    assert math.degrees(servos["hip_far"].target) == pytest.approx(40)  # the swing leg
    tap(s, "space")
    s.handle(ev.mouse(0.0, 0.5))
    assert s.runtime.state == "far_stance"
    assert math.degrees(servos["hip_near"].target) == pytest.approx(-10)  # now the near leg


def test_guide_foot_placement_snippet_adds_to_the_swing_hip(tmp_path):
    s = doc_session(tmp_path, "c_d = 30 deg per m")
    s.advance(480)
    hip = s.character.servos["hip_far"]
    c = s.character
    d = c.com()[0] - c.link_position("foot_near")[0]
    v = c.com_velocity()[0]
    base = math.radians(c.spec.start.joints["hip_far"])
    assert hip.target == pytest.approx(base + math.radians(30 * d + 12 * v), abs=1e-3)


def test_guide_cat_lunge_reaches_when_the_back_paws_leave_the_ground(tmp_path):
    s = doc_session(tmp_path, "name: cat-lunge")
    s.advance(240)
    tap(s, "x")
    s.advance(240)
    tap(s, "space")
    states = set()
    for _ in range(180):
        s.advance(4)
        states.add(s.runtime.state)
    assert {"pushing", "flying"} <= states  # the back paws left the ground: reach
    assert s.runtime.state == "ready"  # landed (or timed out) and ready again


def test_the_climbing_example_catches_the_next_bar(tmp_path):
    """Section 16: mounted on the first bar, `w` then `d` put the far hand on bar 2."""
    text = [t for _, t in guide_blocks()
            if t.startswith("# file: interfaces/bars-example.yaml")][-1]
    path = tmp_path / "interfaces" / "bars-example.yaml"
    path.parent.mkdir()
    path.write_text(text, encoding="utf-8")
    s = Session(load_setup(str(path)))
    s.advance(round(3.0 / s.sim.dt))
    assert sorted(s.sim.grasps) == ["hand_far", "hand_near"]  # mounted on bar 1
    assert s.runtime.states == {"main": "near_support", "legs": "tucked"}
    for key, wait in (("w", 0.5), ("d", 0.5)):
        s.handle(ev.key(key, True))
        s.handle(ev.key(key, False))
        s.advance(round(wait / s.sim.dt))
    bars = s.sim.props["bars"]
    assert math.dist(s.sim.grasp_point("hand_far"), bars.point_world("bar2")) < 1e-6
    assert math.dist(s.sim.grasp_point("hand_near"), bars.point_world("bar1")) < 1e-6


def test_guide_rigid_grasp_keeps_the_held_angle(tmp_path):
    """Section 8.5: the swing caught rigidly; the upper arm keeps its angle to the bar."""
    s = doc_session(tmp_path, "grasp: true, tolerance: 0.03, rigid: true}")
    s.advance(240)
    tap(s, "g")
    arm, bar = s.character.bodies["upper_arm"], s.sim.props["swing"].body
    angles, swing = [], []
    for _ in range(60):
        s.advance(20)
        if "shade" in s.sim.rigid:
            angles.append(arm.angle - bar.angle)
            swing.append(bar.angle)
    assert len(angles) > 40 and max(angles) - min(angles) < 0.002
    assert max(swing) - min(swing) > 0.1  # the bar turns, with the lamp on it
    tap(s, "u")
    s.advance(1)
    assert not s.sim.rigid and not s.sim.grasps


# -- docs/scripts.md's commands, run as written ------------------------------------------
SHIPPED = ("characters", "interfaces", "assets/scenes", "assets/scripts")  # what they read


def doc_commands(path: Path) -> list[str]:
    """Every ``puppet`` command of a page, in its order: the lines of its ```sh blocks
    (a trailing '# comment' dropped) and inline `puppet SUBCOMMAND ARG...` spans."""
    text = path.read_text(encoding="utf-8")
    found = []
    for m in re.finditer(r"```sh\n(.*?)```|`(puppet [^`]+)`", text, re.S):
        if m.group(1) is not None:
            lines = [re.sub(r"\s+#.*", "", ln).strip() for ln in m.group(1).splitlines()]
            found += [(m.start(), ln) for ln in lines if ln.startswith("puppet ")]
        elif len(m.group(2).split()) >= 3:  # `puppet play` alone names the command only
            found.append((m.start(), m.group(2)))
    return [cmd for _, cmd in sorted(found, key=lambda f: f[0])]  # a block's lines in order


def doc_file_names() -> set[str]:
    """The names of the files the docs' examples are (``# file:`` blocks): they do not
    ship, a reader saves them."""
    return {FILE_MARK.match(t.splitlines()[0]).group(2)[:-len(".yaml")]
            for doc in DOC_FILES for _, t in yaml_blocks(doc) if FILE_MARK.match(t.splitlines()[0])}


def test_scripts_doc_commands_run_as_written(tmp_path):
    """Every command of docs/scripts.md runs as written (exit 0), in the page's order,
    from the top folder of a copy of the clone's data files (paths such as
    assets/scripts/luxo-hop.yaml are relative to it; a log it records is the one it
    replays). Those that name no file of
    the docs' own examples run on a fresh clone's files alone, the page's opening
    example among them; the rest run once the examples are saved where the page says
    (the worked example's interfaces/luxo-hopper.yaml, the scripts under their names)."""
    import os
    import shlex
    import shutil
    import subprocess
    import sys

    root = DOCS.parent
    home = tmp_path / "clone"
    for sub in SHIPPED:
        shutil.copytree(root / sub, home / sub)
    env = dict(os.environ, PUPPET_HOME=str(home), SDL_VIDEODRIVER="dummy",
               SDL_AUDIODRIVER="dummy")
    commands = doc_commands(DOCS / "scripts.md")
    ours = doc_file_names()

    def needs_doc_file(cmd: str) -> bool:
        return any(Path(word).stem in ours for word in shlex.split(cmd)[2:])

    first_block = (DOCS / "scripts.md").read_text().split("```sh\n")[1].split("```")[0]
    opening = [c for c in commands if c in first_block]
    assert opening and not any(needs_doc_file(c) for c in opening), opening
    fresh = [c for c in commands if not needs_doc_file(c)]
    later = [c for c in commands if needs_doc_file(c)]
    assert len(fresh) >= 5 and later, commands

    def run(cmd: str) -> None:
        proc = subprocess.run([sys.executable, "-m", "puppet", *shlex.split(cmd)[1:]],
                              cwd=home, env=env, capture_output=True, text=True,
                              timeout=300)
        assert proc.returncode == 0, f"{cmd}\n{proc.stdout}{proc.stderr}"
        assert "Traceback" not in proc.stderr, cmd

    for cmd in fresh:
        run(cmd)
    # save the examples as the page says: the worked example's final interface file,
    # the scripts as the files their first lines name
    (home / "interfaces" / WORKED).write_text(worked_example(tmp_path / "x").read_text())
    for _, text in yaml_blocks(DOCS / "scripts.md"):
        m = FILE_MARK.match(text.splitlines()[0])
        if m:
            (home / m.group(1) / m.group(2)).write_text(text)
    for cmd in later:
        run(cmd)
