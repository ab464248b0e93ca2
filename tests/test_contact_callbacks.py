"""The contact sensors' C callbacks (puppet.physics.character): where they cannot be
made (old-style cffi callbacks need write+execute memory, which some systems forbid)
the module still imports and reads the contacts through pymunk's ``each_arbiter``:
the same readings, the same logs."""

from __future__ import annotations

import pytest

from puppet.physics import character as cmod


@pytest.mark.parametrize("error", [
    MemoryError("Cannot allocate write+execute memory for ffi.callback()"),
    SystemError("ffi_prep_closure(): bad user_data"),
    cmod._ffi.error("no callbacks here"),
])
def test_without_write_execute_memory_there_are_no_callbacks(error):
    def make(kind):
        def build(func):
            raise error
        return build

    assert cmod._arbiter_callbacks(make) is None
    assert cmod._arbiter_callbacks() is not None  # here they can be made


def _without_callbacks(monkeypatch):
    monkeypatch.setattr(cmod, "_COUNT", None)
    monkeypatch.setattr(cmod, "_COLLECT", None)


def test_each_arbiter_reads_what_the_callbacks_read(monkeypatch):
    """Walking, lying and right after a checkpoint re-seats the space: every foot's
    contact and the support extent, read both ways at once."""
    from puppet.commands.bench.subjects import Subject, gesture

    subject = Subject("biped", "biped-floor")
    session = subject.session(keyframes=False)
    frames = gesture(subject.frames(6.0), subject.interface_spec)
    fast = (cmod._COUNT, cmod._COLLECT)
    c = session.character
    touching = 0
    for k, batch in enumerate(frames):
        for event in batch:
            session.handle(event)
        session.advance(subject.steps_per_frame)
        if k % 45 == 0:
            session.sim.checkpoint()
        read = lambda: ([c.in_contact(n) for n in c.bodies], c.support_extent())  # noqa: E731
        cmod._COUNT, cmod._COLLECT = fast
        want = read()
        _without_callbacks(monkeypatch)
        assert read() == want, k
        touching += sum(want[0])
        monkeypatch.undo()
    assert touching > 100


def test_a_log_replays_to_its_hash_without_callbacks(monkeypatch):
    """biped-push-step's states wait for a foot's contact (contact.swing_foot)."""
    from puppet.data.catalog import ROOT
    from puppet.timeline.replay import replay

    _without_callbacks(monkeypatch)
    got = replay(ROOT / "assets" / "logs" / "biped-push-step.jsonl", trajectory=False)
    assert got.same_end is True, got.final_hash
