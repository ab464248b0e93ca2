"""Arms from the clip, legs from the walk keys, in one performance
(assets/logs/biped-walk-mocap-arms): biped-walk.yaml's walk on the mouse and space, its
arm joints tracking a mocap clip after one press of A. The log replays and meets its
expectations in tests/test_logs.py; here: it is driven as it says, its arms' bound
fails without the tracking, and the mocap search (assets/tune/biped-walk-mocap-arms.yaml)
writes a script whose recording does what the search saw."""

from __future__ import annotations

import json

from puppet.data.catalog import ROOT
from puppet.testing import replay_log

LOG = ROOT / "assets" / "logs" / "biped-walk-mocap-arms.jsonl"
ARMS = ["shoulder_near", "elbow_near", "shoulder_far", "elbow_far"]
STEPS_PER_S = 480  # dt 1/480 s


def _lines() -> tuple[str, list[dict]]:
    lines = LOG.read_text(encoding="utf-8").splitlines()
    return lines[0], [json.loads(line) for line in lines[1:]]


def _events() -> list[dict]:
    return [e for e in _lines()[1] if "event" in e]


def test_the_legs_are_on_the_mouse_and_space_and_the_arms_on_the_clip():
    events = _events()
    kinds = {e["event"]["type"] for e in events}
    assert kinds == {"mouse", "key", "action", "channels"}
    keys = [e for e in events if e["event"]["type"] == "key"]
    assert {e["event"]["key"] for e in keys} == {"space", "a"}
    a_down = [e["step"] for e in keys if e["event"]["key"] == "a" and e["event"]["down"]]
    assert a_down == [round(0.1 * STEPS_PER_S)]  # once, before the walk starts
    frames = [e for e in events if e["event"]["type"] == "channels"]
    last = max(e["step"] for e in events)
    assert len(frames) >= 60 * last / STEPS_PER_S - 1  # the clip all along, 60 a second
    # every arm angle in every frame from the press on (the first frame has none: its
    # arms are seen end-on, and a segment never seen in the plane gives no angle)
    assert all(set(ARMS) <= set(e["event"]["values"]) for e in frames
               if e["step"] >= a_down[0])
    moved_late = [e for e in events if e["event"]["type"] == "mouse"
                  and e["step"] > STEPS_PER_S * 10]
    assert len(moved_late) > 100  # the mouse walks the legs all along


def test_without_the_a_press_the_arms_miss_the_bound(tmp_path):
    """The same log with A never pressed: the arms keep the walk's own swing and miss
    the clip's by far more than the log's bound (measured before it falls, 4.8 s)."""
    head, rows = _lines()
    kept = [r for r in rows if not ("event" in r and r["event"].get("type") == "key"
                                    and r["event"].get("key") == "a")]
    assert len(kept) == len(rows) - 2  # the press and the release
    log = tmp_path / "no-arms.jsonl"
    log.write_text("\n".join([head] + [json.dumps(r) for r in kept]) + "\n",
                   encoding="utf-8")
    window = {"joints": ARMS, "from": 1.0, "until": 4.5}
    until = round(4.6 * STEPS_PER_S)  # the window's end: no need to replay on
    result = replay_log(log, until, expect=[{"followed_channels": {**window, "max_rms": 20}},
                                            {"followed_channels": {**window, "min_rms": 40}}])
    passed = [o.passed for o in result.outcomes if o.expectation.startswith("followed")]
    assert passed == [False, True], [str(o) for o in result.outcomes]
    # and with A pressed (the log itself) the same window is within the bound
    with_arms = replay_log(LOG, until,
                           expect=[{"followed_channels": {**window, "max_rms": 20}}])
    assert not with_arms.failed, [str(o) for o in with_arms.outcomes]


def test_the_mocap_search_writes_a_script_whose_recording_does_what_it_saw(tmp_path):
    """assets/tune/biped-walk-mocap-arms.yaml in miniature (a few strides, 4 tries each):
    the clip plays along every try (the spec's ``mocap``), and the written script,
    played by `puppet play --mocap` and recorded, is the search's log to the bit (the
    search merged the clip's samples as the command does) and meets its criteria."""
    from puppet.commands import main as puppet

    spec = (ROOT / "assets" / "tune" / "biped-walk-mocap-arms.yaml").read_text("utf-8")
    spec = (spec.replace("times: 80", "times: 5").replace("min: 18.5}", "min: 0.3}")
            .replace("x_at_end: {com: true, min: 18.0}", "x_at_end: {com: true, min: 0.3}")
            .replace("search: {tries: 32,", "search: {tries: 4,"))
    assert spec.count("min: 0.3}") == 2 and "tries: 4," in spec
    mini = tmp_path / "mini.yaml"
    mini.write_text(spec, encoding="utf-8")
    out, script, log = tmp_path / "tuned.jsonl", tmp_path / "mini-script.yaml", \
        tmp_path / "played.jsonl"
    assert puppet(["tune", str(mini), "--out", str(out), "--script", str(script),
                   "-j", "1"]) == 0
    assert "--mocap cmu-01_01-jumps --mapping cmu-01" in script.read_text("utf-8")
    clip = ["--mocap", "cmu-01_01-jumps", "--mapping", "cmu-01"]
    assert puppet(["play", "biped-walk", "--headless", *clip, "--input", str(script),
                   "--record", str(log)]) == 0
    tuned, played = (p.read_text("utf-8").splitlines()[1:] for p in (out, log))
    assert played == tuned  # every event and the end hash
    frames = [r for r in map(json.loads, played) if r.get("event", {}).get("type") == "channels"]
    assert len(frames) > 60 * 2  # the clip all along (60 a second, over 2 s)
    result = replay_log(log, expect=[
        {"never_fell": True}, {"x_at_end": {"com": True, "min": 0.3}},
        {"tilt_never_above": {"links": ["pelvis", "chest"], "max": 45}},
        {"followed_channels": {"joints": ARMS, "from": 1.0, "max_rms": 20}}])
    assert result.outcomes and not result.failed, [str(o) for o in result.failed]
    assert result.final_hash == result.recorded_hash
