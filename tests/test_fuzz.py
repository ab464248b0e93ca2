"""Fuzzing (hypothesis, seeded): mutated characters, interfaces, scenes, scripts,
expectation files and logs end in acceptance or a clean one-line error, never another
exception, never a hang (2 s) or runaway memory (200 MB); accepted data files and logs
are played for 2 s of simulated time and must not crash.

The default run is bounded (``PUPPET_FUZZ_CASES`` per test, 150 each by default, about
10 s in all); the long run is ``pytest -m fuzz`` (``PUPPET_FUZZ_LONG`` cases per test,
default 7,000: over 20,000 cases in all). The counts per kind and outcome are printed at
the end.
"""

import atexit
import json
import os
import shutil
import tempfile
from pathlib import Path

import fuzzing
import pytest
from fuzzing import KINDS, NASTY_JSON, data_case, log_case, log_lines, mutate_data, mutate_text
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

SHORT = int(os.environ.get("PUPPET_FUZZ_CASES", "150"))
LONG = int(os.environ.get("PUPPET_FUZZ_LONG", "7000"))
TMP = Path(tempfile.mkdtemp(prefix="puppet-fuzz-"))
atexit.register(shutil.rmtree, TMP, ignore_errors=True)


def _settings(n):
    return settings(max_examples=n, derandomize=True, database=None, deadline=None,
                    suppress_health_check=list(HealthCheck), print_blob=True)


OPS = st.lists(st.tuples(st.integers(0, 8), st.integers(0, 10**6), st.integers(0, 10**4)),
               min_size=1, max_size=4)
LEAF = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.sampled_from([0, 1, -1, 0.5, 1e308, -1e308, 1e-320, 255, 256, 3600, 3601]),
    st.text(max_size=30), st.sampled_from(["../../etc/passwd", "/etc/hosts", "x" * 300]),
    st.booleans(), st.none(),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
    st.dictionaries(st.text(max_size=8), st.integers(), max_size=3),
)
PATH = st.lists(st.integers(0, 1000), min_size=1, max_size=7)
TEXTS = {kind: [(p, p.read_text(encoding="utf-8")) for p in paths]
         for kind, paths in KINDS.items()}


def _check(result):
    assert result.outcome in ("accepted", "refused"), (result.outcome, result.detail)


def _text_case(kind, which, ops):
    path, text = TEXTS[kind][which % len(TEXTS[kind])]
    return data_case(kind, mutate_text(text, ops), TMP / f"t-{kind}", path)


def _data_case(kind, which, path, value):
    src, text = TEXTS[kind][which % len(TEXTS[kind])]
    data = fuzzing.located_data(src)
    mutated = mutate_data(data, path, value)
    return data_case(kind, fuzzing.yaml_text_of(mutated), TMP / f"d-{kind}", src)


def _log_case(which, line, ops, field_path, value, how):
    lines = log_lines(which)
    i = line % len(lines)
    if how == 0:  # text mutation of one line
        lines[i] = mutate_text(lines[i], ops)
    elif how == 1:  # a field becomes a nasty JSON value
        try:
            obj = json.loads(lines[i])
            lines[i] = json.dumps(mutate_data(obj, field_path, "@@"), allow_nan=True)
            nasty = NASTY_JSON[(value if isinstance(value, int) else line) % len(NASTY_JSON)]
            lines[i] = lines[i].replace('"@@"', nasty, 1)
        except ValueError:
            pass
    elif how == 2:  # a field becomes a random value
        try:
            obj = json.loads(lines[i])
            lines[i] = json.dumps(mutate_data(obj, field_path, value), allow_nan=True)
        except ValueError:
            pass
    elif how == 3:  # the embedded interface text is mutated
        try:
            header = json.loads(lines[0])
            header["interface_text"] = mutate_text(str(header.get("interface_text", "")), ops)
            lines[0] = json.dumps(header)
        except (ValueError, AttributeError):
            pass
    else:  # lines dropped, repeated or reordered
        j = (line * 7 + value if isinstance(value, int) else line) % len(lines)
        lines[i], lines[j] = lines[j], lines[i]
        if how == 5:
            lines.insert(j, lines[i])
    return log_case(lines, TMP / "log")


def _kinds_test(n):
    @_settings(n)
    @given(kind=st.sampled_from(sorted(KINDS)), which=st.integers(0, 20), ops=OPS)
    def text_mutants(kind, which, ops):
        _check(_text_case(kind, which, ops))

    @_settings(n)
    @given(kind=st.sampled_from(sorted(KINDS)), which=st.integers(0, 20), path=PATH,
           value=LEAF)
    def data_mutants(kind, which, path, value):
        _check(_data_case(kind, which, path, value))

    @_settings(n)
    @given(which=st.integers(0, 2), line=st.integers(0, 10**4), ops=OPS, field_path=PATH,
           value=st.one_of(st.integers(0, 10**4), LEAF), how=st.integers(0, 5))
    def log_mutants(which, line, ops, field_path, value, how):
        _check(_log_case(which, line, ops, field_path, value, how))

    return text_mutants, data_mutants, log_mutants


_short = _kinds_test(SHORT)
_long = _kinds_test(LONG)


def test_fuzz_data_file_text():
    _short[0]()


def test_fuzz_data_file_values():
    _short[1]()


def test_fuzz_logs():
    _short[2]()


@pytest.mark.fuzz
def test_fuzz_long_data_file_text():
    _long[0]()


@pytest.mark.fuzz
def test_fuzz_long_data_file_values():
    _long[1]()


@pytest.mark.fuzz
def test_fuzz_long_logs():
    _long[2]()


def test_harness_sees_a_crash_and_a_hang(monkeypatch):
    """The harness would report what it is there to find. (The hang at a tenth of the
    cases' CPU bound: the same path, ``time_limit``'s Hang, without spinning 2 s; the
    bound itself is the next test's.)"""
    monkeypatch.setattr(fuzzing, "CASE_SECONDS", fuzzing.CASE_SECONDS / 10)
    assert fuzzing.run_case("self-test", lambda: 1 / 0).outcome == "uncaught"
    assert fuzzing.run_case("self-test", lambda: None, lambda: {}["x"]).outcome \
        == "accepted-then-crash"

    def spin():
        while True:
            pass

    assert fuzzing.run_case("self-test", spin).outcome == "hang"


def test_the_hang_bound_is_cpu_time_and_a_blocked_case_meets_the_wall_bound():
    """A case is bounded by the CPU time it uses, not by the wall clock (a loaded
    machine stretches that); a case that waits, using none, meets the wall bound."""
    import resource
    import time

    def cpu():
        usage = resource.getrusage(resource.RUSAGE_SELF)
        return usage.ru_utime + usage.ru_stime

    start = cpu()
    with pytest.raises(fuzzing.Hang, match="CPU time"), fuzzing.time_limit(0.2, wall=30):
        while True:
            pass
    assert cpu() - start >= 0.15  # (the timer counts in clock ticks)
    slept = time.perf_counter()
    with fuzzing.time_limit(0.05, wall=30):
        time.sleep(0.3)  # 0.3 s of wall time, next to no CPU: not a hang
    assert time.perf_counter() - slept >= 0.3
    with pytest.raises(fuzzing.Hang, match="wall time"), fuzzing.time_limit(5, wall=0.2):
        time.sleep(2)
