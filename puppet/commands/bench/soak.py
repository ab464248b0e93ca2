"""The scrubbing soak: does rewinding leak? Resident memory over many rounds of play,
scrub back (the rewind key held: the preview restores keyframes and re-simulates from
them) and release (the exact rewind), on one interface.

Each ``Simulation.restore`` builds a fresh pymunk space, with the cached contacts of
the snapshot's step (``puppet.physics.snapshot``); a scrub restores hundreds of times a
second. Issue 32: each restore leaked about 0.2 kB per contact, so a long session grew
without end. ``soak`` measures the resident set (RSS) after a warm-up (the history's
abandoned futures fill up to ``MAX_BRANCHES`` and then stay), then over ``rounds`` more
rounds or ``seconds`` of wall time; the target is ≤ ``TARGET_MB`` of growth.
``puppet bench --soak MINUTES`` runs it on the cat and the biped; the suite runs a few
hundred rounds (tests/test_restore_leak.py).
"""

from __future__ import annotations

import gc
import time

TARGET_MB = 2.0  # RSS growth allowed over a whole soak
SOAK = {"cat": "cat-trot", "biped": "biped-walk"}  # the characters soaked, by interface
PLAY_STEPS = 480  # played each round before the scrub (1 s at the default dt)
SCRUB_FRAMES = 10  # 60 Hz frames the rewind key is held each round
REWINDS = 20  # exact rewinds to the round's start after each release
WARMUP_ROUNDS = 60  # past MAX_BRANCHES (50): the history's size is steady from here


def rss_mb() -> float:
    """This process's resident set now, MB (Linux ``/proc``; elsewhere its peak)."""
    try:
        with open("/proc/self/statm") as fh:
            import os

            return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6
    except (OSError, ValueError, IndexError):
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3


def malloc_bytes() -> int | None:
    """Bytes the C allocator has handed out and not had back (glibc's ``mallinfo2``:
    Chipmunk's arbiters and spaces, Python's larger objects), or None without glibc.
    Steadier than the RSS, which moves by pages and arenas: a leak of 0.2 kB per
    restore shows in a few hundred restores."""
    import ctypes

    class Info(ctypes.Structure):
        _fields_ = [(name, ctypes.c_size_t) for name in
                    ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                     "fsmblks", "uordblks", "fordblks", "keepcost")]

    try:
        fn = ctypes.CDLL(None).mallinfo2
    except (OSError, AttributeError):
        return None
    fn.restype = Info
    info = fn()
    return int(info.uordblks + info.hblkhd)


def soak(interface: str, rounds: int | None = None, seconds: float | None = None,
         warmup: int = WARMUP_ROUNDS, clock=time.perf_counter) -> dict:
    """Play, scrub back and release ``warmup`` rounds, then measure the RSS over
    ``rounds`` more (or as many as fit in ``seconds`` of ``clock`` time). Returns the
    rounds, the restores the physics made (``Simulation.restore``), the RSS at the start
    of the measure and its growth (MB), and whether it is within ``TARGET_MB``."""
    from puppet.data.catalog import load_setup
    from puppet.physics.simulation import Simulation
    from puppet.session import Session

    if (rounds is None) == (seconds is None):
        raise ValueError("soak: give rounds or seconds")
    from puppet.data.interfaces import CHECKPOINT_MIN

    # the densest keyframes an interface may ask for: a re-seat (a restore) every 0.5 s
    # of play, and the scrub's preview restores one at every interval it crosses
    session = Session(load_setup(interface), checkpoint_interval=CHECKPOINT_MIN)
    restores = [0]
    real_restore = Simulation._rebuild  # every restore, the preview's and checkpoints' too

    def counted(sim, state):
        restores[0] += 1
        return real_restore(sim, state)

    Simulation._rebuild = counted
    try:
        return _soak(session, restores, rounds, seconds, warmup, clock, interface)
    finally:
        Simulation._rebuild = real_restore


def _soak(session, restores, rounds, seconds, warmup, clock, interface) -> dict:
    from puppet.session.history import Scrubber

    k = [0]
    scrub = Scrubber(session)  # one, as the window has

    base = session.steps + PLAY_STEPS  # where each round starts

    def one_round(rewinds: int = REWINDS) -> None:
        k[0] += 1
        x = 0.2 + 0.6 * ((k[0] * 0.381966) % 1.0)  # a new input each round: a new branch
        session.handle({"type": "mouse", "x": x, "y": 1.0 - x})
        session.advance(PLAY_STEPS)
        scrub.start()
        for _ in range(SCRUB_FRAMES):
            scrub.update(1.0 / 60.0)
        scrub.release()
        # back to where the round began (a keyframe: a restore, no re-simulation), to and
        # fro as a user hunting for the moment does; the kept history stays as long, so
        # what it holds is steady once MAX_BRANCHES abandoned futures are kept
        for _ in range(rewinds):
            session.handle({"type": "action", "name": "rewind", "to_step": base})

    session.advance(PLAY_STEPS)

    for _ in range(warmup):
        one_round(rewinds=1)
    gc.collect()
    start_rss, start_malloc = rss_mb(), malloc_bytes()
    start_restores, done = restores[0], 0
    end = None if seconds is None else clock() + seconds
    while (done < rounds) if rounds is not None else (clock() < end):
        one_round()
        done += 1
    gc.collect()
    growth = rss_mb() - start_rss
    made = restores[0] - start_restores
    end_malloc = malloc_bytes()
    per_restore = (None if start_malloc is None or end_malloc is None or not made
                   else (end_malloc - start_malloc) / made)
    return {"interface": interface, "rounds": done, "restores": made,
            "rss_mb": round(start_rss, 2), "growth_mb": round(growth, 3),
            "malloc_per_restore": None if per_restore is None else round(per_restore, 1),
            "target_mb": TARGET_MB, "pass": growth <= TARGET_MB}


def soak_main(minutes: float, as_json: bool = False) -> int:
    """``puppet bench --soak MINUTES``: the soak on the cat and the biped, each for
    ``MINUTES`` of wall time; exit 1 if either grew past ``TARGET_MB``."""
    import json

    results = []
    for name, interface in SOAK.items():
        got = soak(interface, seconds=minutes * 60.0)
        got["character"] = name
        results.append(got)
        if not as_json:
            print(f"soak {name} ({interface}): {got['rounds']} rounds, {got['restores']} "
                  f"restores in {minutes:g} min: RSS {got['rss_mb']:.1f} MB, grew "
                  f"{got['growth_mb']:.2f} MB (target <= {TARGET_MB:g} MB): "
                  f"{'PASS' if got['pass'] else 'MISS'}", flush=True)
    if as_json:
        print(json.dumps({"soak": results}, indent=2))
    return 0 if all(r["pass"] for r in results) else 1
