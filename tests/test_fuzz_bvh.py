"""Fuzzing the BVH reader (issue 11; hypothesis, seeded): mutants of small valid BVH
files (truncated; words deleted, repeated or swapped; numbers made garbage, NaN, inf or
huge; channel and frame counts wrong or huge; hierarchies nested thousands deep; bytes
that are not UTF-8 and characters that are not ASCII; lines deleted, repeated, swapped)
are read with ``read_bvh``. Each must end in a Clip that is consistent (its hierarchy,
channel columns, frame count, the numbers of its frames and a finite forward kinematics
agree with the file) or in a one-line ``DataError`` naming the file and a line of it;
never another exception, never a hang (2 s) or runaway memory (200 MB).

The default run is bounded (``PUPPET_FUZZ_BVH_CASES``, 300 by default, a few seconds);
the long run is ``pytest -m fuzz`` (``PUPPET_FUZZ_BVH_LONG``, default 10,000 cases).
The counts per outcome are printed at the end (kind ``bvh``).
"""

import atexit
import math
import os
import re
import shutil
import tempfile
from pathlib import Path

import fuzzing
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_mocap_bvh import SMALL, WALK

from puppet.data.errors import DataError
from puppet.mocap.bvh import PlanarJoint, read_bvh, write_planar_bvh

SHORT = int(os.environ.get("PUPPET_FUZZ_BVH_CASES", "300"))
LONG = int(os.environ.get("PUPPET_FUZZ_BVH_LONG", "10000"))
TMP = Path(tempfile.mkdtemp(prefix="puppet-fuzz-bvh-"))
atexit.register(shutil.rmtree, TMP, ignore_errors=True)


def _planar() -> str:
    out = TMP / "planar.bvh"
    joints = [PlanarJoint("base", None, (0, 0)), PlanarJoint("arm", "base", (0.0, 0.2)),
              PlanarJoint("hand", "arm", (0.1, 0.0), end=(0.05, 0.0))]
    angles = np.array([[0.0, 10.0, -20.0], [5.0, 15.0, 25.0]])
    write_planar_bvh(out, joints, np.array([[0.0, 0.0], [0.1, 0.0]]), angles, 1 / 30,
                     decimals=3)
    return out.read_text()


def _walk_head(frames: int = 3) -> str:
    """The CMU walk's 31-joint hierarchy (ZXY arms, ZYX legs) and its first frames."""
    lines = WALK.read_text().splitlines()
    at = lines.index("MOTION")
    head = lines[:at] + ["MOTION", f"Frames: {frames}"]
    return "\n".join(head + lines[at + 2:at + 3 + frames]) + "\n"


SOURCES = [SMALL, _planar(), _walk_head(), SMALL.replace("\n", "\r\n")]
NASTY = ["nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e309", "-1e309", "1e308",
         "1e-320", "0", "-0", "1_000", "0x10", "1,5", "1.2.3", "--1", "1e", ".", "+", "e5",
         "9" * 30, "9" * 5000, "٣", "１", "0.0\x00", "", "-", "1e+", "½", "1 2", "\u2028"]
COUNTS = ["-1", "7", "8", "99", "0", "1", "2", "3", "6", "1.0", "+3", "9" * 13, "9" * 5000,
          "٣", "x", ""]
WEIRD = ["é", "☃", "\u2028", "\u2029", "\x85", "\x0c", "\x0b", "\x1c", "\ufeff", "\x00",
         "\t", "\r", "\n", "\xa0", "𝕏", "\udcff", "{", "}", "JOINT", "End Site", "MOTION"]
FINE = ["-0.5", "1e3", "+2", ".5", "3.", "-0", "1E-3", "360", "-720.25", "0.000001",
        "123456.789", "7"]
NAMES = ["é", "☃x", "𝕏", "a{b", "}x", "Hips", "upper", "lower_end", "twist", "x" * 300,
         "End", "JOINT", "MOTION", "l\u2028r", "_end"]
RAW = [b"\xff", b"\xc3", b"\xe2\x80", b"\xed\xa0\x80", b"\x00", b"\xfe\xff"]
WORD = re.compile(r"\S+")
NUM = re.compile(r"(?<!\S)[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?(?!\S)")


def _deep(n: int, channels: bool) -> str:
    """``n`` joints each inside the last (with 0 or 1 channel: the frames must grow)."""
    ch = "CHANNELS 1 Zrotation\n" if channels else ""
    return "".join(f"JOINT d{i}\n{{\nOFFSET 0 1 0\n{ch}" for i in range(n)) + "}\n" * n


def mutate_bvh(text: str, ops: list[tuple[int, int, int]]) -> tuple[str, list[int]]:
    """Apply ``ops`` (operation, where, what: integers drawn by hypothesis); returns the
    text and the raw-byte insertions to make when it is written (position, which)."""
    raw: list[int] = []
    for op, where, what in ops:
        words = list(WORD.finditer(text))
        kind = op % 13
        if kind == 0:  # truncate
            text = text[:where % (len(text) + 1)]
        elif kind == 1 and words:  # delete a word
            m = words[where % len(words)]
            text = text[:m.start()] + text[m.end():]
        elif kind == 2 and words:  # repeat a word (or a run of them)
            i = where % len(words)
            j = min(len(words), i + 1 + what % 4)
            span = text[words[i].start():words[j - 1].end()]
            text = text[:words[i].start()] + span + " " + text[words[i].start():]
        elif kind == 3:  # a number becomes a nasty one
            spots = list(NUM.finditer(text))
            if spots:
                m = spots[where % len(spots)]
                text = text[:m.start()] + NASTY[what % len(NASTY)] + text[m.end():]
        elif kind == 4:  # a channel count, or the frame count, goes wrong
            spots = [m for m in re.finditer(r"(CHANNELS|Frames:)[ \t]+(\S+)", text)]
            if spots:
                m = spots[where % len(spots)]
                new = COUNTS[what % len(COUNTS)]
                if m.group(1) == "Frames:" and what % 3 == 0:
                    new = str(int(m.group(2)) + (what % 5) - 2) if m.group(2).isdigit() else new
                text = text[:m.start(2)] + new + text[m.end(2):]
        elif kind == 5 and words:  # swap two words
            a, b = sorted((words[where % len(words)], words[what % len(words)]),
                          key=lambda m: m.start())
            if a.start() != b.start():
                text = (text[:a.start()] + b.group() + text[a.end():b.start()] + a.group()
                        + text[b.end():])
        elif kind == 6:  # nest a chain of joints thousands deep before a '}'
            closes = [m.start() for m in re.finditer(r"(?m)^[ \t]*\}", text)]
            if closes:
                at = closes[where % len(closes)]
                n = (1, 2, 50, 1500, 5000)[what % 5]
                text = text[:at] + _deep(n, channels=what % 7 == 0) + text[at:]
        elif kind == 7:  # a character that is not ASCII, a control or a keyword
            i = where % (len(text) + 1)
            text = text[:i] + WEIRD[what % len(WEIRD)] + text[i:]
        elif kind == 8:  # a byte that is not UTF-8, written into the file
            raw.append(where)
            raw.append(what % len(RAW))
        elif kind == 9:  # a frame line added, dropped or made ragged
            lines = text.split("\n")
            i = where % len(lines)
            if what % 3 == 0:
                lines.insert(i, lines[i])
            elif what % 3 == 1:
                del lines[i]
            else:
                lines[i] = lines[i] + " 0" * (1 + what % 3)
            text = "\n".join(lines)
        elif kind == 10:  # a number becomes another (valid) one
            spots = list(NUM.finditer(text))
            if spots:
                m = spots[where % len(spots)]
                text = text[:m.start()] + FINE[what % len(FINE)] + text[m.end():]
        elif kind == 11:  # a joint gets another name
            spots = list(re.finditer(r"(?:ROOT|JOINT)[ \t]+(\S+)", text))
            if spots:
                m = spots[where % len(spots)]
                text = text[:m.start(1)] + NAMES[what % len(NAMES)] + text[m.end(1):]
        else:  # the generic text mutations of the other fuzz tests
            text = fuzzing.mutate_text(text, [(op, where, what)])
    return text, raw


def _bytes_of(text: str, raw: list[int]) -> bytes:
    data = text.encode("utf-8", errors="surrogatepass")
    for k in range(0, len(raw), 2):
        i = raw[k] % (len(data) + 1)
        data = data[:i] + RAW[raw[k + 1]] + data[i:]
    return data


def _frame_numbers(text: str) -> list[float]:
    """The numbers after the 'Frame Time:' line, read independently of the reader."""
    tail = re.split(r"(?m)^[ \t]*Frame Time:.*$", text, maxsplit=1)[1]
    return [float(w) for w in tail.split()]


def check_clip(clip, text: str, path: str) -> None:
    """What an accepted file's Clip must satisfy."""
    joints = clip.joints
    assert joints and joints[0].parent == -1 and not joints[0].end_site
    assert len(set(clip.names)) == len(joints), "joint names must be unique"
    first = 0
    for i, j in enumerate(joints):
        assert clip.index(j.name) == i
        assert i == 0 or 0 <= j.parent < i and not joints[j.parent].end_site
        assert j.offset.shape == (3,) and np.isfinite(j.offset).all()
        assert len(j.channels) <= 6 and len(set(j.channels)) == len(j.channels)
        assert not (j.end_site and j.channels)
        assert j.first_channel == first
        first += len(j.channels)
    assert clip.motion.shape == (clip.frames, first) and clip.motion.dtype == float
    assert np.isfinite(clip.motion).all()
    assert math.isfinite(clip.frame_time) and clip.frame_time > 0 and math.isfinite(clip.fps)
    assert clip.path == path
    if first:  # the frames hold the file's numbers, in order
        assert clip.motion.ravel().tolist() == _frame_numbers(text)
    if clip.frames and max(np.abs(clip.motion).max(initial=0),
                           max(np.abs(j.offset).max() for j in joints)) < 1e6:
        pos = clip.world_positions()
        assert pos.shape == (clip.frames, len(joints), 3) and np.isfinite(pos).all()


WHERE = re.compile(r"^(?P<path>.+?\.bvh):(?P<line>\d+)(?::\d+)?: \S")


def bvh_case(source: int, ops, tmp: Path, kind: str = "bvh") -> fuzzing.Result:
    text, raw = mutate_bvh(SOURCES[source % len(SOURCES)], ops)
    tmp.mkdir(parents=True, exist_ok=True)
    path = tmp / "m.bvh"
    path.write_bytes(_bytes_of(text, raw))
    read = path.read_text(encoding="utf-8", errors="replace")  # what the reader sees
    read = read.replace("\r\n", "\n").replace("\r", "\n")  # its line ends
    lines = read.count("\n") + 1
    clip = []

    def parse():
        try:
            clip.append(read_bvh(path))
        except DataError as exc:
            m = WHERE.match(str(exc))
            assert m and m["path"] == str(path), f"no file:line in {exc}"
            assert 1 <= int(m["line"]) <= lines, f"line {m['line']} of {lines}: {exc}"
            raise

    return fuzzing.run_case(kind, parse, lambda: check_clip(clip[0], read, str(path)))


def _settings(n):
    return settings(max_examples=n, derandomize=True, database=None, deadline=None,
                    suppress_health_check=list(HealthCheck), print_blob=True)


OPS = st.lists(st.tuples(st.integers(0, 12), st.integers(0, 10**6), st.integers(0, 10**4)),
               min_size=1, max_size=4)


def _bvh_test(n):
    @_settings(n)
    @given(source=st.integers(0, len(SOURCES) - 1), ops=OPS)
    def bvh_mutants(source, ops):
        result = bvh_case(source, ops, TMP / "case")
        assert result.outcome in ("accepted", "refused"), (result.outcome, result.detail)

    return bvh_mutants


def test_the_sources_are_read_and_consistent():
    for text in SOURCES:
        assert bvh_case(SOURCES.index(text), [], TMP / "src", "self-test").outcome == "accepted"


def test_fuzz_bvh_reader():
    _bvh_test(SHORT)()


@pytest.mark.fuzz
def test_fuzz_long_bvh_reader():
    _bvh_test(LONG)()


def test_the_bvh_harness_sees_a_wrong_clip_and_a_wrong_line(monkeypatch, tmp_path):
    """The checks would report what they are there to find."""
    import puppet.mocap.bvh as bvh

    assert bvh_case(0, [], tmp_path, "self-test").outcome == "accepted"
    real = bvh.Clip.__post_init__

    def drop_a_frame(self):
        real(self)
        self.motion = self.motion[1:]

    monkeypatch.setattr(bvh.Clip, "__post_init__", drop_a_frame)
    assert bvh_case(0, [], tmp_path, "self-test").outcome == "accepted-then-crash"
    monkeypatch.undo()

    def wrong_line(path, line, col, message):
        return DataError(path, 10**6, col, message)

    monkeypatch.setattr(bvh, "DataError", wrong_line)
    truncated = bvh_case(0, [(0, 5, 0)], tmp_path, "self-test")  # an error on line 1
    assert truncated.outcome == "uncaught" and "line 1000000 of 1" in truncated.detail
