"""Three bugs planted by hand that the whole suite let through (issue 32): an ``add``
map that drops its per-joint gains, an ``any_state`` key that wins over a state's own
binding of the same key, and a log header's ``checkpoint_interval`` without its upper
bound. Each test here fails on its bug (checked by planting it again)."""


import pytest
from helpers import session_of as make
from test_log_hardening import MOUSE, header, write
from test_maps import deg

from puppet.data.errors import DataError
from puppet.data.interfaces import CHECKPOINT_MAX
from puppet.interface import events as ev
from puppet.timeline.log import read_log


def test_an_add_map_scales_each_joint_by_its_own_gain(tmp_path):
    """``joints: {knee: 0.5, ankle: -2}``: each joint gets its gain times the value
    (docs/interfaces.md, coupling), added to what set it."""
    s = make(tmp_path, """
    name: t
    description: one contribution, two joints, two gains
    character: luxo
    maps:
      - {input: channel.a, joints: {knee: 0.5, ankle: -2}, from: [0, 1], to: [0, 10],
         combine: add}
    """)
    base = deg(s)
    s.handle(ev.channels({"a": 1.0}))
    s.advance(1)
    got = deg(s)
    assert got["knee"] == pytest.approx(base["knee"] + 5.0)
    assert got["ankle"] == pytest.approx(base["ankle"] - 20.0)
    s.handle(ev.channels({"a": 0.5}))  # a contribution, not a running sum
    s.advance(16)  # the next control step
    assert deg(s)["knee"] == pytest.approx(base["knee"] + 2.5)
    assert deg(s)["ankle"] == pytest.approx(base["ankle"] - 10.0)


def test_a_states_own_key_wins_over_the_same_any_state_key(tmp_path):
    """The guide (section 7.6): an any_state key works in every state; a state's own
    binding of the same key wins in that state."""
    s = make(tmp_path, """
    name: t
    description: t bound in one state and in any_state
    character: luxo
    initial: rest
    states:
      rest:
        keys:
          - {key: t, goto: own}
      own: {}
      shared: {}
    any_state:
      keys:
        - {key: t, goto: shared}
        - {key: g, goto: rest}
    """)
    main = s.runtime.machines["main"]

    def press(key):
        s.handle(ev.key(key, True))
        s.handle(ev.key(key, False))
        return main.current

    assert main.current == "rest"
    assert press("t") == "own"  # the state's own binding
    assert press("t") == "shared"  # elsewhere: any_state's
    assert press("g") == "rest" and s.runtime.binding("t").goto == "own"
    assert press("t") == "own"


@pytest.mark.parametrize("value", [1e300, CHECKPOINT_MAX + 0.5, 1e6])
def test_a_log_headers_checkpoint_interval_has_an_upper_bound(tmp_path, value):
    text = header(checkpoint_interval=value)
    path = write(tmp_path, [text, MOUSE])
    with pytest.raises(DataError) as info:
        read_log(path)
    assert info.value.line == 1 and "'checkpoint_interval'" in info.value.message
    assert "\n" not in str(info.value)


def test_a_log_headers_checkpoint_interval_may_be_the_largest(tmp_path):
    path = write(tmp_path, [header(checkpoint_interval=CHECKPOINT_MAX), MOUSE])
    assert read_log(path).header["checkpoint_interval"] == CHECKPOINT_MAX
