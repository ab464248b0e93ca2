"""``puppet tune``: specs refused in one line, the same log whatever runs the tries, a
search resumed after an interruption, a search that improves its score, stages from
checkpoints that replay straight through, interface numbers, a generator, the cluster.

Every search here is a few tries of a second or two of Luxo (a tenth of a second of
CPU each), on the in-process executor unless the test is about another one.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from puppet.data.errors import DataError
from puppet.timeline.executor import Executor, make_executor
from puppet.timeline.tuning import Interrupted, Search, load_tune_spec
from puppet.timeline.tuning.trial import TryResult
from puppet.timeline.tuning.writer import write_all

HOP = """
description: One hop forward on the mouse.
interface: luxo-mouse
scene: flat
seed: 3
events:
  - {t: 0.0, mouse: [0.656, 0.583]}
feat:
  expect:
    - x_at_end: {link: base, min: 0.05}
    - upright_at_end: true
stages:
  - name: hop
    at: 0.1
    vary:
      cx: [0.8, 1.0]
      cy: [0.1, 0.3]
      hold: [0.4, 0.7]
      px: [0.05, 0.25]
      py: [0.3, 0.5]
    first: {cx: 0.8, cy: 0.3, hold: 0.4, px: 0.25, py: 0.5}
    let:
      push: 0.2 + hold
    events:
      - {t: 0.05, mouse: [cx, cy], over: 0.15}
      - {t: push, mouse: [px, py], over: 0.03}
      - {t: push + 0.23, mouse: [0.58, 0.582], over: 0.15}
      - {t: push + 0.88, mouse: [0.656, 0.583], over: 0.3}
    length: push + 1.6
    search: {tries: %(tries)d, climbs: 1, refine: %(refine)d}
    score:
      - expect: {x_at_end: {link: base, min: 0.0}}
        points: 0
        weight: 10
        cap: 1.0
"""


def spec_file(tmp_path: Path, text: str, name: str = "hop.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def hop(tmp_path, tries=6, refine=0, name="hop.yaml"):
    return load_tune_spec(spec_file(tmp_path, HOP % {"tries": tries, "refine": refine}, name))


def events_of(log: Path) -> list[str]:
    """The log's lines less its header (which names the puppet version and files)."""
    return log.read_text(encoding="utf-8").splitlines()[1:]


# -- specs refused in one line --------------------------------------------------------
@pytest.mark.parametrize("case", range(9))
def test_a_bad_spec_is_one_line_at_its_place(tmp_path, case):
    text = HOP % {"tries": 2, "refine": 0}
    if case == 0:
        text = text.replace("push: 0.2 + hold", "push: 0.2 + hould")
        want = "unknown name 'hould'"
    elif case == 1:
        text = text.replace("over: 0.03}", "over: lol(1)}")
        want = "'lol' is not allowed"
    elif case == 2:
        text = text.replace("first: {cx: 0.8,", "first: {cx: 1.7,")
        want = "outside cx's range"
    elif case == 3:
        text = text.replace("x_at_end: {link: base, min: 0.05}",
                            "x_at_end: {link: bass, min: 0.05}")
        want = "unknown link 'bass'"
    elif case == 4:
        text = text.replace("search: {tries:", "search: {trys:")
        want = "trys"
    elif case == 5:
        text = text.replace("cx: [0.8, 1.0]", "cx: [1.0, 0.8]")
        want = "the high end is under the low one"
    elif case == 6:  # a clip that is not there
        text = text.replace("seed: 3\n", "seed: 3\nmocap: {clip: no-such-clip}\n")
        want = "no-such-clip"
    elif case == 7:  # a clip plays from the first step: not from a log's middle
        text = text.replace("seed: 3\n", "seed: 3\nmocap: {clip: cmu-01_01-jumps}\n"
                            "start: {log: luxo-hop}\n")
        want = "starts from the scene"
    else:  # a generator's input would miss the clip's samples
        text = text.replace("seed: 3\n", "seed: 3\nmocap: {clip: cmu-01_01-jumps}\n")
        text = text.replace("    length: push + 1.6", "    generator: key-turn\n"
                            "    length: push + 1.6")
        want = "a generator plays its own input"
    path = spec_file(tmp_path, text)
    with pytest.raises(DataError) as exc:
        Search(load_tune_spec(path))
    message = str(exc.value)
    assert "\n" not in message and want in message, message
    assert message.startswith(f"{path}:") and message.split(":")[1].isdigit(), message


def test_the_command_says_a_bad_spec_in_one_line_and_exits_2(tmp_path, capsys):
    from puppet.commands import main

    path = spec_file(tmp_path, (HOP % {"tries": 2, "refine": 0}).replace(
        "- {t: 0.05, mouse: [cx, cy], over: 0.15}", "- {t: 0.05, key: $cx}"))
    assert main(["tune", str(path), "--out", str(tmp_path / "x.jsonl")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "'$cx': 'cx' is not a 'choose' parameter" in err, err


def test_a_playtest_term_scores_how_often_the_simulated_player_still_lands_it(tmp_path):
    text = (HOP % {"tries": 6, "refine": 6}).replace(
        "    score:\n", "    playtest: {noise: human, tries: 3, weight: 20}\n    score:\n")
    loaded = load_tune_spec(spec_file(tmp_path, text))
    search = Search(loaded)
    result = search.run()
    tries = [TryResult.from_dict(d) for d in search.state.tries.values()]
    kept = result.kept[0].result
    assert kept.accepted and kept.pass_rate in (0.0, 1 / 3, 2 / 3, 1.0)
    # only a try that meets what it requires is played by the simulated player
    assert all(t.pass_rate is not None for t in tries if t.accepted)
    assert all(t.pass_rate is None for t in tries if not t.accepted)
    again = Search(load_tune_spec(spec_file(tmp_path, text, "again.yaml"))).run()
    assert again.kept[0].result.pass_rate == kept.pass_rate  # the same draws each time


def test_a_playtest_term_plays_its_tries_on_cheaper_physics_too(tmp_path):
    """``physics:`` entries: the same simulated player's tries on each setting as well
    (a feat that survives only the shipped physics scores less), from the stage's
    checkpoint reached on that setting."""
    from puppet.timeline.other_physics import OtherPhysics
    from puppet.timeline.tuning.trial import prepared, variant

    text = (HOP % {"tries": 6, "refine": 6}).replace(
        "    score:\n", "    playtest: {noise: human, tries: 2, weight: 20, physics: "
                        "[{step: 1/240}, {solver_passes: 30}]}\n    score:\n")
    search = Search(load_tune_spec(spec_file(tmp_path, text)))
    kept = search.run().kept[0].result
    assert kept.accepted and abs(kept.pass_rate * 6 - round(kept.pass_rate * 6)) < 1e-9  # 2x3
    ctx = search._context(0, 0, 0.1, [])
    coarse, ratio = variant(ctx, OtherPhysics(dt=1 / 240))
    assert ratio == 0.5 and coarse.dt == 1 / 240
    assert coarse.stage_step == round(ctx.stage_step / 2)
    assert [s for s, _ in coarse.prefix] == [round(s / 2) for s, _ in ctx.prefix]
    fewer, _ = variant(ctx, OtherPhysics(iterations=30))
    prep = prepared(fewer, 4)
    prep.back()  # (the search's tries played on from the checkpoint)
    assert prep.session.steps == ctx.stage_step and prep.session.sim.space.iterations == 30


@pytest.mark.parametrize("entry, words", [
    ("{}", "changes 'solver_passes', 'step' or both"),
    ("{step: 1/10}", "'1/10' is not a simulation step from 1/2000 to 1/30 s"),
    ("{solver_passes: 0}", "solver_passes"),
])
def test_a_physics_entry_that_changes_nothing_or_is_out_of_range_is_one_line(
        tmp_path, capsys, entry, words):
    from puppet.commands import main

    text = (HOP % {"tries": 2, "refine": 0}).replace(
        "    score:\n", f"    playtest: {{tries: 2, physics: [{entry}]}}\n    score:\n")
    path = spec_file(tmp_path, text)
    assert main(["tune", str(path), "--out", str(tmp_path / "x.jsonl")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and words in err and "hop.yaml:" in err, err


# -- a search, resumed, on other engines: the same log ---------------------------------
def run_search(loaded, out: Path, executor=None, stop_after=None):
    state = out.with_name(out.stem + ".tune.json")
    search = Search(loaded, executor or Executor(), state, stop_after=stop_after)
    result = search.run()
    return search, result, write_all(loaded, result, out)


def test_a_search_improves_on_its_first_try_and_writes_a_log_that_meets_its_feat(tmp_path):
    loaded = hop(tmp_path, tries=6, refine=10)
    search, result, written = run_search(loaded, tmp_path / "hop.jsonl")
    first = next(iter(search.state.tries.values()))  # the first try played: `first`
    assert result.kept[0].result.score > first["score"] + 1.0
    assert result.found and written.passed, [str(o) for o in written.outcomes]
    assert written.same_as_search
    assert written.sidecar.is_file() and "x_at_end" in written.sidecar.read_text()
    # 6 tries and a climb of at most 10 (it ends early when its steps run out)
    assert 10 <= search.played + search.looked_up <= 16


def test_the_same_seed_gives_the_same_log_whatever_the_jobs(tmp_path):
    loaded = hop(tmp_path, tries=5, refine=4)
    _, one, _ = run_search(loaded, tmp_path / "one.jsonl")
    with make_executor(2) as pool:
        assert pool.workers == 2
        _, two, _ = run_search(loaded, tmp_path / "two.jsonl", pool)
    assert events_of(tmp_path / "one.jsonl") == events_of(tmp_path / "two.jsonl")
    assert one.kept[0].params == two.kept[0].params
    # and another seed is another search
    other = load_tune_spec(spec_file(tmp_path, (HOP % {"tries": 5, "refine": 4}).replace(
        "seed: 3", "seed: 4"), "other.yaml"))
    _, three, _ = run_search(other, tmp_path / "three.jsonl")
    assert three.kept[0].params != one.kept[0].params


def test_an_interrupted_search_resumes_where_it_stopped(tmp_path):
    loaded = hop(tmp_path, tries=6, refine=6)
    whole, _, _ = run_search(loaded, tmp_path / "whole.jsonl")
    out = tmp_path / "resumed.jsonl"
    with pytest.raises(Interrupted):  # killed mid-run: after 5 of its tries
        run_search(loaded, out, stop_after=5)
    state = json.loads(out.with_name("resumed.tune.json").read_text())
    assert len(state["tries"]) == 5 and not out.exists()
    search, result, _ = run_search(loaded, out)
    assert search.played == whole.played - 5
    assert search.looked_up == whole.looked_up + 5
    assert events_of(out) == events_of(tmp_path / "whole.jsonl")
    # a stage edited is other tries: none of the old ones is looked up
    changed = load_tune_spec(spec_file(tmp_path, (HOP % {"tries": 6, "refine": 6}).replace(
        "weight: 10", "weight: 11")))
    again = Search(changed, Executor(), out.with_name("resumed.tune.json"))
    before = len(again.state.tries)
    again.run()
    assert again.looked_up == 0 and len(again.state.tries) == before + again.played


def test_a_later_stage_edited_finds_the_earlier_stages_tries(tmp_path):
    text = STEPS.replace("times: 4", "times: 1").replace(
        "    until:\n      - x_at_end: {link: base, min: 0.12}\n", "") + """  - name: lean
    vary: {x: [0.6, 0.95]}
    events:
      - {t: 0, mouse: [x, 0.5], over: 0.1}
    length: 0.5
    search: {tries: 2, refine: 0}
    score:
      - expect: {mean_speed: {min: 0.0}}
"""
    state = tmp_path / "two.tune.json"
    first = Search(load_tune_spec(spec_file(tmp_path, text, "two.yaml")), Executor(), state)
    first.run()
    assert first.played == 3 + 2
    edited = text[:text.rindex("mean_speed: {min: 0.0}")] + "mean_speed: {min: 0.1}}\n"
    second = Search(load_tune_spec(spec_file(tmp_path, edited, "two.yaml")), Executor(), state)
    second.run()
    assert second.looked_up == 3 and second.played == 2  # the first stage's, looked up


# -- stages from checkpoints, repeated until, backtracking -----------------------------
STEPS = """
interface: luxo-mouse
scene: flat
seed: 1
events:
  - {t: 0.0, mouse: [0.656, 0.583]}
stages:
  - name: rock
    at: 0.2
    times: 4
    until:
      - x_at_end: {link: base, min: 0.12}
    vary: {x: [0.6, 0.95], over: [0.05, 0.2]}
    events:
      - {t: 0, mouse: [x, 0.3], over: over}
      - {t: 0.3, mouse: [0.3, 0.8], over: 0.1}
      - {t: 0.6, mouse: [0.656, 0.583], over: 0.2}
    length: 1.0
    search: {tries: 3, refine: 0}
    score:
      - expect: {mean_speed: {min: 0.0}}
        weight: 10
        cap: 1
"""


def test_stages_repeat_until_their_goal_each_from_a_checkpoint(tmp_path):
    loaded = load_tune_spec(spec_file(tmp_path, STEPS, "steps.yaml"))
    state = tmp_path / "steps.tune.json"
    result = Search(loaded, Executor(), state).run()
    written = write_all(loaded, result, tmp_path / "steps.jsonl", tmp_path / "steps-script.yaml")
    reps = [k.rep for k in result.kept]
    assert reps == list(range(len(reps))) and 1 <= len(reps) <= 4
    assert result.kept[-1].result.until_ok or len(reps) == 4
    from puppet.timeline.log import read_log

    marks = [e.step for e in read_log(written.log).events
             if e.event.get("name") == "checkpoint"]
    assert marks == [round(k.t0 * 480) for k in result.kept]
    assert written.same_as_search  # tried from restored checkpoints, replayed straight
    # and the script it wrote, played and recorded as `puppet play --record` does, too
    from puppet.testing import record_script, replay_log

    again = replay_log(record_script(str(written.script), tmp_path / "again.jsonl"))
    assert again.final_hash == replay_log(written.log).final_hash


def test_with_no_try_meeting_a_stage_it_backtracks_to_an_alternative(tmp_path):
    text = STEPS.replace("times: 4", "times: 1").replace("    until:\n      - x_at_end: "
                                                          "{link: base, min: 0.12}\n", "")
    text = text.replace("search: {tries: 3, refine: 0}", "search: {tries: 3, refine: 0}\n"
                        "    alternatives: 2")
    text += """  - name: fly
    vary: {x: [0.6, 0.95]}
    events:
      - {t: 0, mouse: [x, 0.3], over: 0.1}
    length: 0.5
    search: {tries: 3, refine: 0}
    score:
      - expect: {reached_height: {link: base, min: 5.0}}
        required: true
"""
    loaded = load_tune_spec(spec_file(tmp_path, text, "back.yaml"))
    search = Search(loaded)
    result = search.run()
    assert not result.found
    assert result.message == "stage 2/2 'fly': no try met what it requires (after 2 backtracks)"
    # the first stage's 3 tries; the second's 3 from its best and from each alternative
    assert search.played == 3 + 3 * 3
    assert [k.stage for k in result.kept] == [0, 1]


# -- interface numbers, a generator ---------------------------------------------------
def test_interface_numbers_are_varied_by_a_reload_and_written_back_in_place(tmp_path):
    from puppet.timeline.tuning.interface_values import with_values

    text = "# gains\ngains:\n  ankle: {stiffness: 36, damping: 0.45}  # kept\n"
    assert with_values(text, "x.yaml", {"gains.ankle.stiffness": 30.25}) == \
        "# gains\ngains:\n  ankle: {stiffness: 30.25, damping: 0.45}  # kept\n"
    spec = (HOP % {"tries": 2, "refine": 0}).replace(
        "      py: [0.3, 0.5]\n",
        "      py: [0.3, 0.5]\n      knee: {range: [20, 28], interface: [gains.knee.stiffness]}\n")
    loaded = load_tune_spec(spec_file(tmp_path, spec))
    _, result, written = run_search(loaded, tmp_path / "gains.jsonl")
    from puppet.timeline.log import read_log

    reloads = [e for e in read_log(written.log).events if e.event["type"] == "reload"]
    assert len(reloads) == 1 and reloads[0].step == round(0.1 * 480)
    knee = result.kept[0].params["knee"]
    tuned = written.interface.read_text()
    import yaml

    assert yaml.safe_load(tuned)["gains"]["knee"]["stiffness"] == knee
    assert "# Stiffer and stronger" in tuned  # the file's comments kept
    assert written.same_as_search
    bad = spec.replace("gains.knee.stiffness", "gains.knee.stifness")
    with pytest.raises(DataError, match="gains.knee.stifness: no 'stifness' there"):
        load_tune_spec(spec_file(tmp_path, bad, "bad.yaml"))


def test_a_generator_stage_is_kept_as_the_entries_it_wrote(tmp_path):
    spec = """
interface: biped-gymnast
seed: 1
stages:
  - name: pump
    generator: giant-swings
    vary: {pike_x: [0.6, 0.8], pike_y: [0.5, 0.8]}
    first: {pike_x: 0.71, pike_y: 0.67}
    let: {arch_x: 0.2, arch_y: 0.2, glide: 0.08, lo: 0, hi: 180, delay: 0, start: 0.3}
    length: 2.0
    search: {tries: 1, refine: 0}
    score:
      - expect: {swung: {about: [0.0, 2.8], min: 5}}
        weight: 1
        cap: 30
"""
    loaded = load_tune_spec(spec_file(tmp_path, spec, "pump.yaml"))
    _, result, written = run_search(loaded, tmp_path / "pump.jsonl")
    entries = result.kept[0].entries
    assert entries[0] == {"t": 0.0, "mouse": [0.2, 0.2]}
    assert any(e["mouse"] == [0.71, 0.67] for e in entries[1:])  # it pumped
    assert written.same_as_search


# -- the cluster engine ---------------------------------------------------------------
def test_a_local_dask_cluster_of_two_workers_gives_the_same_log(tmp_path):
    pytest.importorskip("distributed")
    loaded = hop(tmp_path, tries=3, refine=2)
    _, here, _ = run_search(loaded, tmp_path / "here.jsonl")
    with make_executor(2, cluster="local") as dask:
        assert dask.workers == 2 and "Dask" in dask.name
        _, there, _ = run_search(loaded, tmp_path / "there.jsonl", dask)
        from puppet.data.playtest import LEVELS
        from puppet.timeline.playtest import Plan
        from puppet.timeline.playtest import run as run_plans

        plan = Plan(str(tmp_path / "here.jsonl"), LEVELS["human"], "human", 4, 0)
        on_dask = run_plans([plan], executor=dask)[0]
    assert events_of(tmp_path / "here.jsonl") == events_of(tmp_path / "there.jsonl")
    here_plays = run_plans([plan])[0]
    assert [r.final_hash for r in on_dask.results] == [r.final_hash for r in here_plays.results]


# -- the docs' worked example, and every shipped spec ---------------------------------
DOCS = Path(__file__).resolve().parents[1] / "docs" / "tuning.md"
SPECS = Path(__file__).resolve().parents[1] / "assets" / "tune"


def test_the_worked_example_runs_as_the_docs_say(tmp_path, capsys, monkeypatch):
    import re
    import shlex

    from puppet.commands import main

    text = DOCS.read_text(encoding="utf-8")
    block = re.search(r"```yaml\n# file: assets/tune/luxo-first-hop.yaml\n(.*?)```", text,
                      re.S).group(1)
    assert block == (SPECS / "luxo-first-hop.yaml").read_text(encoding="utf-8")
    line = next(cmd for cmd in re.findall(r"^puppet tune .*$", text, re.M)
                if "--script" in cmd)
    args = shlex.split(line.split("#")[0])[1:]
    args[args.index("--script") + 1] = str(tmp_path / "hop.yaml")
    monkeypatch.chdir(Path(__file__).resolve().parents[1])
    code = main(args + ["--out", str(tmp_path / "hop.jsonl")])
    out = capsys.readouterr().out
    assert code == 0, out
    shown = re.search(r"```\n(stage 1/1 'hop'.*?)```", text, re.S).group(1).splitlines()
    for want in [shown[0]] + [s for s in shown if s.startswith("  ok")] + [shown[-1]]:
        if "wrote" not in want:
            assert want.replace("luxo-first-hop", "hop") in out, want
    assert (tmp_path / "hop.yaml").is_file() and (tmp_path / "hop.expect.yaml").is_file()


@pytest.mark.parametrize("name", sorted(p.stem for p in SPECS.glob("*.yaml")))
def test_every_shipped_spec_is_valid_and_names_a_shipped_feat(name):
    loaded = load_tune_spec(SPECS / f"{name}.yaml")
    Search(loaded)  # its names checked against the character, its start prepared
    assert loaded.spec.feat is not None and loaded.spec.feat.expect


def test_a_search_can_begin_at_a_logs_checkpoint(tmp_path):
    text = """
start: {log: luxo-shuffle, checkpoint: 1}
stages:
  - name: lean
    vary: {x: [0.6, 0.9]}
    events:
      - {t: 0, mouse: [x, 0.4], over: 0.1}
    length: 0.5
    search: {tries: 2, refine: 0}
    score:
      - expect: {mean_speed: {min: 0.0}}
"""
    loaded = load_tune_spec(spec_file(tmp_path, text, "from-log.yaml"))
    search = Search(loaded)
    result = search.run()
    written = write_all(loaded, result, tmp_path / "from-log.jsonl", tmp_path / "x.yaml")
    from puppet.timeline.log import read_log

    source = read_log(SPECS.parents[0] / "logs" / "luxo-shuffle.jsonl")
    ours = read_log(written.log)
    assert ours.header["interface"] == source.header["interface"] == "luxo-shuffle"
    cut = [i for i, e in enumerate(source.events) if e.event.get("name") == "checkpoint"][0]
    assert [(e.step, e.event) for e in ours.events[:cut + 1]] == \
        [(e.step, e.event) for e in source.events[:cut + 1]]
    assert result.kept[0].t0 == 0.3 and written.same_as_search
    assert written.script is None and "began from a log" in written.notes[0]
    bad = text.replace("checkpoint: 1", "checkpoint: 3")
    with pytest.raises(DataError, match="luxo-shuffle has 1 checkpoint"):
        Search(load_tune_spec(spec_file(tmp_path, bad, "bad.yaml")))
