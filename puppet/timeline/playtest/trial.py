"""One try of a playtest: a log's input moved by the human model, replayed headless,
judged by the log's feat expectations.

The feat is what the expectations say (the sidecar ``LOG.expect.yaml`` wins over the
header's, as for ``puppet replay --check``); the recorded end state is not a feat, so
neither the end line's hash nor a ``final_hash`` entry is judged. A try that blows up
(or leaves the world) fails: the physics saved the run, not the player.

A log recorded from a reactive script (its header keeps the script: ``script_text``)
is played in its tries by that script (``puppet.timeline.reactive``), its rules
reacting to what each try does, with the noise on its timed events and reaction
delays; input given by hand alongside the script is not part of those tries.

What a log needs for its tries (read, its setup loaded, its expectations, the slowdown
at each event) is prepared once per process (``prepare``), so a worker running many
tries of one log pays for it once.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path

from puppet.data.catalog import Setup
from puppet.data.errors import DataError
from puppet.data.playtest import Noise
from puppet.timeline.expectations import Expectations, evaluate_all, load_expectations, sidecar_path
from puppet.timeline.log import Log, LogEvent, read_log
from puppet.timeline.other_physics import OtherPhysics
from puppet.timeline.playtest.noise import Perturbation, perturb
from puppet.timeline.playtest.slowdown import in_force
from puppet.timeline.reactive import ScriptPlayer, Speed, play_script
from puppet.timeline.replay import apply_log, find_log, new_session, require_end, setup_for_log
from puppet.timeline.script import ScriptSpec
from puppet.timeline.trajectory import Sampler, sample_every

NOT_FEATS = ("final_hash",)  # expectation kinds that say which bits, not what was done


@dataclass
class Prepared:
    """A log ready for tries."""

    path: str
    log: Log
    setup: Setup
    expectations: Expectations  # the feat's (NOT_FEATS left out)
    slowdowns: list[float]  # in force at each event
    app_keys: dict[str, str]
    warnings: list[str] = field(default_factory=list)  # replay's and loading's, one line each
    script: ScriptSpec | None = None  # the reactive script that plays the tries, if any


@dataclass
class TryResult:
    """What one try did. ``failed``: the expectations it missed, one line each
    ('FAIL kind ...: measured'), and a line per blow-up."""

    index: int
    passed: bool
    failed: list[str]
    final_hash: str
    steps: int

    def to_dict(self) -> dict:
        return asdict(self)


_PREPARED: dict[tuple, Prepared] = {}
SHIPPED = OtherPhysics()  # the log's own physics settings


def _mtime(path: Path) -> int | None:
    """A file's modification time (None: none), so that an edited log or sidecar is
    prepared again."""
    try:
        return path.stat().st_mtime_ns
    except OSError:
        return None


def prepare(name: str, physics: OtherPhysics = SHIPPED) -> Prepared:
    """The log called ``name`` (a path or a log's name) ready for tries, on ``physics``
    (other solver passes or another step: the log's events moved to the same times, as
    ``puppet replay --step`` moves them); cached per process. DataError for a log that
    cannot be replayed or has no feat to judge."""
    path = find_log(name)
    key = (str(Path(path).resolve()), _mtime(Path(path)), _mtime(sidecar_path(path)),
           physics)
    if key in _PREPARED:
        return _PREPARED[key]
    log = read_log(path)
    require_end(log, allow_truncated=False)
    setup, warnings = setup_for_log(log)
    log, setup = physics.log(log), physics.adjust(setup)
    expectations = load_expectations(path, log.header)
    warnings += expectations.notes
    feats = [e for e in expectations.items if e.kind not in NOT_FEATS]
    if not feats:
        side = Path(path).name.removesuffix(".jsonl") + ".expect.yaml"
        raise DataError(path, None, None, "no feat expectations to judge a try by (the "
                                          "recorded end state is not a feat); write what "
                                          f"the performance must show in {side}")
    expectations.items = feats
    session = new_session(log, setup)  # a link the character lacks: said before any try
    expectations.check_links(list(session.character.link_order))
    prepared = Prepared(path, log, setup, expectations, in_force(log, setup),
                        setup.interface.app_key_table(), warnings, _script(log, setup))
    _PREPARED[key] = prepared
    return prepared


def _script(log: Log, setup: Setup) -> ScriptSpec | None:
    """The reactive script a log's header keeps (None: none, or one without rules)."""
    text = log.header.get("script_text")
    if not isinstance(text, str):
        return None
    from puppet.data.yamlfile import load_text
    from puppet.timeline.script import check_links, parse_script

    where = f"{log.path} (header: script_text)"
    located = load_text(text, where)
    spec = parse_script(located)
    if not spec.rules:
        return None
    check_links(where, spec, [link.name for link in setup.character.links],
                setup.interface, setup.character, located)
    return spec


def perturbation(prepared: Prepared, noise: Noise, seed: int, index: int) -> Perturbation:
    """Try ``index``'s moved events (see ``noise.perturb``)."""
    log = prepared.log
    return perturb(log.pairs(), prepared.slowdowns, float(log.header["dt"]), log.last_step,
                   noise, seed, index, prepared.app_keys)


def perturbed_log(prepared: Prepared, noise: Noise, seed: int, index: int) -> Log:
    """A copy of the log (in memory) with try ``index``'s moved events; its end line
    keeps the step and drops the hash (the state reached is not judged)."""
    log = prepared.log
    moved = perturbation(prepared, noise, seed, index).pairs
    return Log(log.path, dict(log.header), [LogEvent(s, e, 0) for s, e in moved],
               {"end": log.last_step})


def judge(prepared: Prepared, log: Log | None = None, noise: Noise | None = None,
          seed: int = 0, index: int = 0) -> TryResult:
    """Replay ``log`` (one of ``prepared``'s tries, or the log itself) headless and
    judge it by the feat expectations; with no ``log``, the log's reactive script
    plays (at ``noise``, for try ``index`` from ``seed``; None: as written)."""
    session = new_session(prepared.log, prepared.setup)
    sampler = Sampler(session, touches=prepared.expectations.touches)
    sampler(session)
    if log is not None:
        apply_log(session, log, None, sample_every(session.sim.dt), sampler)
    else:
        speed = Speed(float(prepared.log.header.get("slowdown") or 1.0))
        player = ScriptPlayer(session, prepared.script, prepared.log.last_step, speed,
                              speed.apply, noise, seed, index)
        play_script(session, player, sample_every(session.sim.dt), sampler)
    if not sampler.rows or sampler.rows[-1][0] != session.steps:
        sampler(session)
    final = session.sim.state_hash()
    outcomes = evaluate_all(prepared.expectations.items, sampler.trajectory(), final)
    failed = [str(o) for o in outcomes if not o.passed]
    failed += [f"FAIL blow-up: {note}" for note in session.blowup_messages]
    return TryResult(-1, not failed, failed, final, session.steps)


def run_try(name: str, noise: Noise, seed: int, index: int,
            physics: OtherPhysics = SHIPPED) -> TryResult:
    """Try ``index`` of the log called ``name`` at ``noise`` from ``seed`` (on
    ``physics``): the same arguments give the same result, bit for bit, in any
    process."""
    prepared = prepare(name, physics)
    if prepared.script is not None:
        result = judge(prepared, None, noise, seed, index)
    else:
        result = judge(prepared, perturbed_log(prepared, noise, seed, index))
    result.index = index
    return result
