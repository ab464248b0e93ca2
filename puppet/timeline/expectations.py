"""What a replayed log must show: checked by ``puppet replay --check`` and test suites.

Expectations live in the log header (``"expect": [...]``) or in a sidecar file
``LOG.expect.yaml`` next to the log (``expect:`` then a list); the sidecar wins (the
header's entries are then not checked, a warning says so; an empty list, which checks
nothing, is a warning too). Each entry names one check (every kind is listed here):

    expect:
      - x_at_end: {link: base, min: 0.5}       # x of the link's centre of mass at the end, m
      - x_at_end: {com: true, max: 2.0}        # ... or of the whole character's
      - height_at_end: {link: pelvis, min: 0.8, held: 1.0}
                                  # the link's centre of mass (m above y = 0) within
                                  # min..max at the end (held: at every sample of the
                                  # last 1 s): standing, not crouched or fallen
      - upright_at_end: true                   # root within 45 deg of upright at the end
      - never_fell: true                       # root never more than 90 deg from upright
                                               # while touching the ground
      - tilt_never_above: {links: [pelvis, chest], max: 45}
                                  # each link within 45 deg of upright at every sample
      - tilt_at_end: {links: [pelvis, chest], max: 15, held: 1.0}
                                  # each link within 15 deg of upright at every sample of
                                  # the last 1 s (held 0: the last sample)
      - touching_at_end: {links: [foot_near, foot_far], held: 1.0, min_fraction: 0.95}
                                  # each link touching the ground at (at least 95% of) the
                                  # samples of the last 1 s: both feet down
      - followed_channels: {joints: [hip_near, knee_near], from: 4.3, until: 6.7,
                            max_rms: 10}
                                  # each joint within 10 deg RMS of the input channel of
                                  # its name (a retargeted mocap angle) over that window
      - reached_height: {link: base, min: 0.05}
                                  # the link's lowest point rose >= 5 cm above its start
      - airborne: {link: base, min_seconds: 0.1}
                                  # the link out of contact for 0.1 s in one stretch
      - airborne: {link: base, max_seconds: 0.1}
                                  # ... and never for more than 0.1 s at a time (a shuffle)
      - stood_on: {link: upper_arm, min_seconds: 2.0, min_tilt: 135}
                                  # balanced on that link alone (the only one touching),
                                  # the root at least 135 deg from upright (upside
                                  # down: a headstand), for 2 s in one stretch
      - balanced_on: {links: [forearm_near, forearm_far], min_seconds: 2.0,
                      above: [foot_near, foot_far], over: head}
                                  # only these links touch the ground (one or more of
                                  # them at every sample), the root at least min_tilt
                                  # (135) deg from upright, each 'above' link's centre of
                                  # mass higher than the 'over' link's, for 2 s in one
                                  # stretch: a handstand on both hands, feet over the head
      - got_up: {lay_seconds: 1.0, within_seconds: 1.5}
                                  # lay (root >= min_tilt, 80 deg, from upright while
                                  # touching) for 1 s, then from the end of the last
                                  # such stretch stood up (root within upright_tilt,
                                  # 20 deg) within 1.5 s, and stayed up to the end
      - turned: {link: base, min_degrees: 300, direction: backward}
                                  # the link's accumulated rotation, start to end, at
                                  # least 300 deg backward (counter-clockwise for a
                                  # character facing +x; forward is clockwise)
      - turned: {link: base, min_degrees: 270, direction: backward, in_flight: true}
                                  # ... turned within one stretch with no link touching
      - landed_at: {link: base, min: 6.0}
                                  # where the longest flight ended (the longest stretch
                                  # with no link touching): the link's x at touchdown, m
      - took_off: {links: [foot_near, foot_far], max_x: -0.08, min_seconds: 0.25}
                                  # the longest flight lasted 0.25 s and began from only
                                  # these links, each (its centre of mass) at x <= -0.08
                                  # at the last sample on the ground: behind a line
      - on_ground: {links: [thigh_near, thigh_far], min_seconds: 1.0, min_root_angle: 30}
                                  # all these links touching the ground at every sample of
                                  # one stretch of 1 s, the root tipped at least 30 deg
                                  # backward (signed: counter-clockwise, for a character
                                  # facing +x) all the while: sat down on its seat, back
      - angle_within: {link: pelvis, min: 70, until: 0.5}
                                  # the link's signed angle from upright (deg, -180..180,
                                  # counter-clockwise +: tipped backward for a character
                                  # facing +x) within min..max at every sample from
                                  # 'from' (default the start) to 'until' (the end):
                                  # lying on its back at the start; a max over 180
                                  # takes the angle in max-360..max (a range across
                                  # upside down): {min: -70, max: 200} over the whole
                                  # run: never turned onto its front (-160..-70)
      - first_touch: {links: [foot_near, foot_far], min_x: 0.3}
                                  # what touched first when the longest flight ended:
                                  # only these links, each at x >= 0.3 (feet first, in
                                  # the pit)
      - bent_after_flight: {links: [thigh_near, thigh_far], from_link: chest,
                            min: -30, max: 100, within: 0.1}
                                  # at some sample from the end of the longest flight
                                  # to 0.1 s later, each link's angle minus from_link's
                                  # (deg, -180..180, counter-clockwise +) in min..max:
                                  # thighs from the chest, the hips and waist not
                                  # folded over the legs at the landing
      - touched: {links: [foot_near, foot_far], min_height: 0.2, min_x: 0.5,
                  before_flight: true}
                                  # at some sample one of these links touched with its
                                  # lowest point at least 0.2 m up (x >= 0.5): a foot on
                                  # a wall, not on the floor (before_flight: before the
                                  # longest flight, which it pushed off into)
      - mean_speed: {from: 0.0, until: 5.0, max: 1.0}
                                  # the centre of mass's mean forward speed (its x moved
                                  # over the window's length), m/s, between the samples
                                  # nearest 'from' and 'until' (default: the start, the end)
      - flight_phases: {from: 20.0, min_count: 5, min_seconds: 0.04,
                        links: [foot_near, foot_far]}
                                  # at least 5 stretches that begin in the window with
                                  # none of the links touching (default: no link of the
                                  # character), each lasting 0.04 s or more: a run's
                                  # flights, not a one-sample bounce; max_count: at
                                  # most so many ({min_count: 2, max_count: 2}: exactly
                                  # two hops)
      - run_up: {links: [foot_near, foot_far], min_flights: 3, flight_seconds: 0.04,
                 min_speed: 1.5, over: 1.0}
                                  # before the longest flight (the jump, the flight
                                  # took_off and first_touch measure): at least 3
                                  # flights with none of the links touching, 0.04 s or
                                  # more each, ended before it (within: s, only those
                                  # begun that long before it), and the centre of mass's
                                  # mean forward speed over its last 1.0 s on the ground
                                  # at least 1.5 m/s: a run-up, not a walk-up
      - stayed_in_state: upright               # the interface's state machine was in
                                               # 'upright' at every sample of the run
      - stayed_in_state: {state: sitting, from: 0.6, until: 4.0}
                                  # ... from t = 0.6 s to t = 4.0 s (both optional)
      - stayed_in_mode: {mode: keys, from: 1.0}   # the same for the interface's mode
      - revolutions: {about: hand_near, min: 3}
                                  # full turns in a row of the centre of mass about the
                                  # point the chain holds (or about: [x, y], m), never
                                  # turning back more than slack (10 deg): giant swings
      - swung: {about: [0.0, 4.4], min: 20, from: 25.0}
                                  # the centre of mass's angle about that point (deg from
                                  # straight below it, + toward +x) reached min on both
                                  # sides in the window (from, until: s): a swing on a
                                  # rope, not a still hang
      - held: {chains: [hand_near, hand_far], prop: bar, from: 0.0}
                                  # each chain held the prop at every sample (until: s)
      - in_state_at_end: upright               # the state at the end
      - in_mode_at_end: keys                   # the mode at the end
      - held_point: {prop: bars, point: bar7}  # some chain (or 'chain: NAME') held
                                               # that grasp point of the prop at a sample
      - always_holding: {chains: [hand_near, hand_far], from: 3.0}
                                  # at every sample from t = 3 s (to 'until', default the
                                  # end) at least one of the chains held something: it
                                  # never fell off
      - regrasps: {chains: [hand_near, hand_far], prop: bars, min: 6, alternate: true}
                                  # at least 6 new grasps, each of a grasp point further
                                  # along the prop's list than any those chains held
                                  # before (the next bar, the rung above), in a row by
                                  # turns (hand over hand) with 'alternate'
      - mostly_within: {link: chest, max_tilt: 25, min_fraction: 0.8, from: 3.0}
                                  # the link within bounds at (at least) 80% of the samples
                                  # of the window: within 25 deg of upright; x_min / x_max
                                  # (m, its centre of mass: near the ladder); below: LINK
                                  # (its centre of mass lower than that link's: a foot
                                  # under the hips) - each sample must meet all of them
      - final_hash: 0123456789abcdef           # the exact final state

Bounds that nothing can meet are refused when the file is read (``puppet check``):
a ``max`` under its ``min`` (``x_min``/``x_max``, ``min_seconds``/``max_seconds``...),
an ``until`` before its ``from``. ``puppet check LOG`` also refuses a window that
begins after the log's end and, as the replay does, a state or mode the interface
(any version the log plays) does not define.

"Upright" is the root link's angle from its model orientation, taken modulo full
turns. A fall is the root more than 90 deg from upright while any link of the
character touches the ground: a somersault in the air that lands upright is not one.
The first sample (step 0, before the first step) takes the contacts of the next one:
pymunk has none yet, and a standing start would read as a flight.
The trajectory is sampled every few steps (``Trajectory``), so "never" and
"for 0.1 s" are as fine as that sampling (1/120 s by default); so is "stayed": a
state left and re-entered between two samples goes unseen. A state or mode the
interface does not define is a DataError at the entry, raised when the expectations
are evaluated: the interface is only known for sure once replayed (the header's copy,
or the versions a reload brought in).
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field as dc_field
from pathlib import Path
from typing import Annotated, ClassVar, Literal

import numpy as np

from puppet.data.errors import DataError
from puppet.data.playtest_bar import PlaytestBar
from puppet.data.ranges import Num, Time
from puppet.data.validate import Meta, Spec, at, field, validate
from puppet.data.yamlfile import Located, load_file

Measure = Num("measure")
UPRIGHT_DEG = 45.0  # upright_at_end tolerance (Character.upright's default)
FELL_DEG = 90.0  # never_fell: beyond this from upright is a fall


class XAtEnd(Spec, kw_only=True):
    link: str | None = None  # link whose centre of mass is measured
    com: bool = False  # measure the whole character's centre of mass
    min: Measure | None = None
    max: Measure | None = None

    def __post_init__(self):
        if (self.link is None) == (not self.com):
            raise ValueError("give either 'link: NAME' or 'com: true'")
        if self.min is None and self.max is None:
            raise ValueError("give 'min', 'max' or both")


class HeightAtEnd(Spec, kw_only=True):
    """The link's centre of mass (m above y = 0) within bounds at the end, and (``held``)
    over the last ``held`` s: standing, not fallen or crouched."""

    link: str
    min: Num("measure") | None = None
    max: Num("measure") | None = None
    held: Num("duration") = 0.0  # s at the end it must stay in bounds

    def __post_init__(self):
        if self.min is None and self.max is None:
            raise ValueError("give 'min' and/or 'max' (m)")


class TiltNeverAbove(Spec, kw_only=True):
    """Each of ``links`` stays within ``max`` degrees of its model orientation (upright)
    at every sample: a trunk that never leans past 45 degrees."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    max: Num("angle")  # deg from upright


class TiltAtEnd(Spec, kw_only=True):
    """Each of ``links`` within ``max`` degrees of its model orientation (upright) at
    every sample of the last ``held`` s (0: the last sample): standing up straight at
    the end, not only not having fallen."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    max: Num("angle")  # deg from upright
    held: Num("duration") = 0.0  # s at the end it must stay within


class TouchingAtEnd(Spec, kw_only=True):
    """Each of ``links`` touching the ground at the samples of the last ``held`` s (0:
    the last sample), at least ``min_fraction`` of them: both feet down at the end. A
    fraction, because a checkpoint re-seats the space and the sample at that step sees
    no contacts yet (pymunk rebuilds them in the next step)."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    held: Num("duration") = 0.0  # s at the end
    # share of those samples touching, at least
    min_fraction: Annotated[float, Meta(ge=0, le=1)] = 1.0


class FollowedChannels(Spec, kw_only=True):
    """Each of ``joints`` moved like the performance: its angle within ``max_rms``
    degrees RMS of the input channel of its name (the retargeted mocap angle) over the
    samples from ``from`` to ``until`` s that have a value for it. ``min_rms``: at least
    one of them strayed that far (the figure reacted to something: a push)."""

    joints: Annotated[list[str], Meta(min_length=1, max_length=64)]
    from_: Time = field(name="from", default=0.0)
    until: Time | None = None
    max_rms: Num("angle") | None = None  # deg
    min_rms: Num("angle") | None = None  # deg

    def __post_init__(self):
        if self.max_rms is None and self.min_rms is None:
            raise ValueError("give 'max_rms' and/or 'min_rms' (deg)")


class ReachedHeight(Spec, kw_only=True):
    link: str
    min: Measure  # m the link's lowest point must rise above its start


class Airborne(Spec, kw_only=True):
    link: str
    min_seconds: Time | None = None  # s out of contact in one stretch, at least
    max_seconds: Time | None = None  # s out of contact in one stretch, at most (every stretch)

    def __post_init__(self):
        if self.min_seconds is None and self.max_seconds is None:
            raise ValueError("give 'min_seconds', 'max_seconds' or both")


class StoodOn(Spec, kw_only=True):
    link: str  # the one link touching the ground
    min_seconds: Time  # s in one stretch
    # deg the root is from upright at least (135: upside down)
    min_tilt: Annotated[float, Meta(ge=0, le=180)] = 135.0


class BalancedOn(Spec, kw_only=True):
    """Only ``links`` touch the ground (at least one of them), the root at least
    ``min_tilt`` from upright and each of ``above`` higher than ``over``, for
    ``min_seconds`` in one stretch: a handstand, on both hands, feet above the head."""

    # the links that may touch; nothing else does
    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    min_seconds: Time  # s in one stretch
    min_tilt: Annotated[float, Meta(ge=0, le=180)] = 135.0  # deg the root is from upright at least
    # links whose centre of mass is above over's
    above: Annotated[list[str], Meta(max_length=64)] = field(default_factory=list)
    over: str | None = None  # the link they are above (the head)

    def __post_init__(self):
        if bool(self.above) != (self.over is not None):
            raise ValueError("give 'above' (a list of links) and 'over' (a link) together")


class GotUp(Spec, kw_only=True):
    lay_seconds: Time  # s lying first, in one stretch
    within_seconds: Time  # s from the end of the last lying stretch to standing up for good
    # deg from upright, touching the ground: lying
    min_tilt: Annotated[float, Meta(ge=0, le=180)] = 80.0
    upright_tilt: Annotated[float, Meta(ge=0, le=180)] = 20.0  # deg from upright at most: standing


class Turned(Spec, kw_only=True):
    link: str
    min_degrees: Num("turn")  # deg of accumulated rotation
    # backward = counter-clockwise (the model faces +x)
    direction: Literal["backward", "forward"] = "backward"
    # count only the turn made in one stretch with no link of the character touching
    in_flight: bool = False


class LandedAt(Spec, kw_only=True):
    link: str
    min: Measure  # m: x of the link when the longest flight ended


class TookOff(Spec, kw_only=True):
    """The longest flight (no link of the character touching) began from ``links`` only
    (those touching at the last sample before it), each with its centre of mass at
    ``max_x`` or less, and lasted ``min_seconds``: a take-off behind a line."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    max_x: Measure | None = None  # m: x of each take-off link, at most
    min_seconds: Time = 0.0  # s the flight lasted, at least


class FirstTouch(Spec, kw_only=True):
    """When the longest flight ended, only ``links`` touched (at the first sample on
    the ground again), each with its centre of mass at ``min_x`` or more: feet first,
    in the pit."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    min_x: Measure | None = None  # m: x of each touching link, at least


class BentAfterFlight(Spec, kw_only=True):
    """At some sample from the end of the longest flight (the first sample down again)
    to ``within`` s later, each of ``links`` was turned from ``from_link`` by at most
    ``max`` (and at least ``min``) deg: the link's angle minus ``from_link``'s, in
    -180..180, counter-clockwise positive. For a figure facing +x, thighs from the
    chest: how far the hips and waist together are folded (+ forward), a landing with
    the trunk up, not folded over the legs."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    from_link: str
    min: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, at least
    max: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, at most
    within: Time  # s after the touch-down, at most

    def __post_init__(self):
        if self.min is None and self.max is None:
            raise ValueError("give 'min' and/or 'max' (deg)")
        if self.min is not None and self.max is not None and self.max <= self.min:
            raise ValueError(f"'max' ({self.max:g}) must be greater than 'min' ({self.min:g})")


class Touched(Spec, kw_only=True):
    """At some sample one of ``links`` touched the ground with its lowest point at least
    ``min_height`` m up and its centre of mass at x >= ``min_x`` (when given): a foot
    planted on a wall, not on the floor below it."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    min_height: Measure  # m: the link's lowest point above y = 0, at least
    min_x: Measure | None = None  # m: x of the link, at least
    before_flight: bool = False  # only the samples before the longest flight count (pushed off it)


class OnGround(Spec, kw_only=True):
    """All of ``links`` touching the ground at every sample of one stretch of at least
    ``min_seconds``, the root's signed angle (deg, counter-clockwise positive: tipped
    backward for a character facing +x) within ``min_root_angle``..``max_root_angle``
    over it: sat down on the seat and leaning back, not only touching."""

    links: Annotated[list[str], Meta(min_length=1, max_length=64)]
    min_seconds: Time  # s in one stretch
    # deg, signed (+ = tipped backward)
    min_root_angle: Annotated[float, Meta(ge=-180, le=180)] | None = None
    # deg, signed (+ = tipped backward)
    max_root_angle: Annotated[float, Meta(ge=-180, le=180)] | None = None
class AngleWithin(Spec, kw_only=True):
    """The link's signed angle from upright (deg, -180..180, counter-clockwise positive:
    tipped backward for a character facing +x) within ``min``..``max`` at every sample
    from ``from`` to ``until`` s: on its back at the start, never on its front."""

    link: str
    min: Annotated[float, Meta(ge=-180, le=180)] | None = None  # deg, signed
    # deg, signed; over 180 the angle is taken in max-360..max: a range across upside down
    max: Annotated[float, Meta(ge=-180, le=540)] | None = None
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def __post_init__(self):
        if self.min is None and self.max is None:
            raise ValueError("give 'min' and/or 'max' (deg)")
        if self.min is not None and self.max is not None and self.max <= self.min:
            raise ValueError(f"'max' ({self.max:g}) must be greater than 'min' ({self.min:g})")
        # a range that holds every angle checks nothing: the angle is taken in
        # max-360..max (-180..180 without a max)
        low = -180.0 if self.max is None else max(-180.0, self.max - 360.0)
        if (self.min is None or self.min <= low) and (self.max is None or self.max >= 180):
            raise ValueError("this range holds every angle; expected a 'min' above "
                             f"{low:g} or a 'max' under 180")


class Swung(Spec, kw_only=True):
    """The centre of mass's angle about ``about`` (deg from straight below it, positive
    toward +x) reached at least ``min`` on both sides (forward and back) between
    ``from`` and ``until`` s: the body swings (on a rope, under a bar) that far, not a
    still hang."""

    about: tuple[Num("world_xy"), Num("world_xy")]  # m: the point
    min: Num("angle")  # deg each way, at least
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)


class MeanSpeed(Spec, kw_only=True):
    """The centre of mass's mean speed along +x over a window: how far it moved between
    the samples nearest ``from`` and ``until`` divided by the time between them (m/s)."""

    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)
    min: Measure | None = None
    max: Measure | None = None

    def __post_init__(self):
        if self.min is None and self.max is None:
            raise ValueError("give 'min', 'max' or both (m/s)")
        if self.until is not None and self.until <= self.from_:
            raise ValueError("'until' must be later than 'from'")


class FlightPhases(Spec, kw_only=True):
    """At least ``min_count`` (and at most ``max_count``) flights that begin inside the
    window: stretches of samples with none of ``links`` touching (default: no link of
    the character), each at least ``min_seconds`` long (from the first sample off to the
    first sample down again). Exactly two hops: ``min_count: 2, max_count: 2``."""

    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)
    min_count: Annotated[int, Meta(ge=1, le=100000)] | None = None  # flights, at least
    max_count: Annotated[int, Meta(ge=0, le=100000)] | None = None  # flights, at most
    min_seconds: Time  # s a flight lasts, at least
    # the links off the ground (default: all)
    links: Annotated[list[str], Meta(min_length=1, max_length=64)] | None = None

    def __post_init__(self):
        if self.min_count is None and self.max_count is None:
            raise ValueError("give 'min_count', 'max_count' or both (flights)")


class RunUp(Spec, kw_only=True):
    """Before the longest flight (no link of the character touching: the jump), at
    least ``min_flights`` flights with none of ``links`` touching (default: no link),
    each ``flight_seconds`` or longer and over before the jump began (``within``: only
    those begun at most that long before it), and the centre of mass's mean speed along
    +x over the ``over`` s before the jump at least ``min_speed``: a run-up.

    The jump is the longest flight, as it is for took_off, first_touch, landed_at,
    bent_after_flight and touched's before_flight: none of them picks the flight by a
    take-off line (took_off's ``max_x`` and first_touch's ``min_x`` check where the
    longest flight began and ended, they do not choose it), so a log's entries all speak
    of one flight. A longer flight elsewhere (a bounce out of the pit, a short jump)
    moves all of them to it together, and took_off's and first_touch's bounds then fail
    the log; picking the flight across a line here would need a line run_up does not
    have, and could pass a run-up to a flight the other entries do not measure."""

    # the links off the ground (default: all)
    links: Annotated[list[str], Meta(min_length=1, max_length=64)] | None = None
    min_flights: Annotated[int, Meta(ge=0, le=100000)] = 0  # flights, at least
    flight_seconds: Time = 0.04  # s a flight lasts, at least
    within: Time | None = None  # s before the jump a flight begins, at most
    min_speed: Measure | None = None  # m/s over the last 'over' s, at least
    over: Time = 1.0  # s before the jump the speed is measured over

    def __post_init__(self):
        if self.min_flights == 0 and self.min_speed is None:
            raise ValueError("give 'min_flights', 'min_speed' or both")
        if self.over <= 0:
            raise at("over", "'over' must be more than 0 s")


class StayedIn(Spec, kw_only=True):
    """The common part of stayed_in_state and stayed_in_mode: the time window. The
    shorthand ``stayed_in_state: NAME`` is the whole run."""

    column: ClassVar[str]  # the Trajectory column and the key naming it: state or mode
    from_: Time | None = field(name="from", default=None)  # s: window start (default: the start)
    until: Time | None = None  # s: window end (default: the end; before 'from': refused
    # with every kind's bounds, Expectations)

    @property
    def name(self) -> str:
        return getattr(self, self.column)


class StayedInState(StayedIn, kw_only=True):
    column: ClassVar[str] = "state"
    state: str  # the interface state it must stay in


class StayedInMode(StayedIn, kw_only=True):
    column: ClassVar[str] = "mode"
    mode: str  # the interface mode it must stay in


class Revolutions(Spec, kw_only=True):
    """Full turns in a row of the centre of mass about a point: giant swings."""

    # a chain (the point it holds, at each sample) or [x, y] in the scene, m
    about: str | tuple[Num("world_xy"), Num("world_xy")]
    min: Num("turns")  # full turns in one stretch, at least
    # backward = counter-clockwise (the model faces +x)
    direction: Literal["either", "backward", "forward"] = "either"
    slack: Num("turn") = 10.0  # deg it may turn back inside the stretch (jitter at the top)


class Held(Spec, kw_only=True):
    """Each of ``chains`` held a grasp (on ``prop``) at every sample of the window."""

    chains: Annotated[list[str], Meta(min_length=1, max_length=16)]
    prop: str | None = None  # the prop held (default: any, or the world)
    from_: Time | None = field(name="from", default=None)  # s: window start
    until: Time | None = None  # s: window end (default: the end)


AT_END = {"in_state_at_end": "state", "in_mode_at_end": "mode"}  # key -> column


class HeldPoint(Spec, kw_only=True):
    """A grasp point of a prop held at some sample (by ``chain``, or by any chain)."""

    prop: str
    point: str  # the prop's grasp point (its name in the scene)
    chain: str | None = None  # the chain that held it (default: any)


class AlwaysHolding(Spec, kw_only=True):
    """At every sample of the window at least one of ``chains`` holds something (a grasp
    point, a segment or a world point): hanging on, never fallen off."""

    chains: Annotated[list[str], Meta(min_length=1, max_length=64)]
    from_: Time | None = field(name="from", default=None)  # s (default: the start)
    until: Time | None = None  # s (default: the end)


class Regrasps(Spec, kw_only=True):
    """New grasps that make progress along a prop: a chain of ``chains`` taking hold of
    a grasp point later in the prop's list than any point those chains held before (the
    next bar, the rung above). ``alternate``: counted only in a row of turns, each by
    another chain than the one before (hand over hand); the longest such row counts."""

    chains: Annotated[list[str], Meta(min_length=1, max_length=64)]
    prop: str
    min: Annotated[int, Meta(ge=1)]  # progressing grasps, at least
    alternate: bool = False


class MostlyWithin(Spec, kw_only=True):
    """``link`` within every bound given at at least ``min_fraction`` of the samples from
    ``from`` to ``until`` s: ``max_tilt`` deg from upright, its centre of mass's x within
    ``x_min``..``x_max`` m, and lower than ``below``'s. A posture held most of the time
    (the trunk upright and close to a ladder), not at every sample: a climb's strokes
    pass through other postures."""

    link: str
    max_tilt: Annotated[float, Meta(ge=0, le=180)] | None = None  # deg from upright, at most
    x_min: Measure | None = None  # m: x of the centre of mass, at least
    x_max: Measure | None = None  # m: x of the centre of mass, at most
    below: str | None = None  # a link whose centre of mass is higher
    min_fraction: Annotated[float, Meta(gt=0, le=1)]  # share of the window's samples
    from_: Time = field(name="from", default=0.0)  # s: window start
    until: Time | None = None  # s: window end (default: the end)

    def __post_init__(self):
        if all(b is None for b in (self.max_tilt, self.x_min, self.x_max, self.below)):
            raise ValueError("give at least one of 'max_tilt', 'x_min', 'x_max', 'below'")
        if self.until is not None and self.until <= self.from_:
            raise at("until", "'until' must be later than 'from'")
        if self.x_min is not None and self.x_max is not None and self.x_max <= self.x_min:
            raise ValueError(f"'x_max' ({self.x_max:g}) must be greater than 'x_min' "
                             f"({self.x_min:g})")

    def describe(self) -> str:
        bounds = ", ".join(b for b in (
            f"within {self.max_tilt:g} deg of upright" if self.max_tilt is not None else "",
            f"x >= {self.x_min:g} m" if self.x_min is not None else "",
            f"x <= {self.x_max:g} m" if self.x_max is not None else "",
            f"below {self.below}" if self.below is not None else "") if b)
        return (f"mostly_within {self.link} {bounds} at {self.min_fraction:g} of the samples "
                f"from {self.from_:g} s to {_until(self)}")

    def evaluate(self, e, traj) -> Outcome:
        desc = self.describe()
        if self.below is not None and self.below not in traj.links:
            raise e.error(f"unknown link '{self.below}'; the character has: "
                          f"{', '.join(traj.links)}", "below")
        idx = _samples_in(traj.t, self.from_, self.until)
        if len(idx) == 0:
            return _no_samples(desc, traj.t)
        k = traj.index(self.link)
        ok = np.ones(len(idx), dtype=bool)
        parts = []
        if self.max_tilt is not None:
            tilt = _tilt_deg(traj.angle[idx, k])
            ok &= tilt <= self.max_tilt
            parts.append(f"tilt within {self.max_tilt:g} deg at "
                         f"{np.mean(tilt <= self.max_tilt):.0%}")
        if self.x_min is not None or self.x_max is not None:
            x = traj.x[idx, k]
            lo = -np.inf if self.x_min is None else self.x_min
            hi = np.inf if self.x_max is None else self.x_max
            inside = (x >= lo) & (x <= hi)
            ok &= inside
            parts.append(f"x {x.min():.2f}..{x.max():.2f} m, in bounds at {np.mean(inside):.0%}")
        if self.below is not None:
            under = traj.y[idx, k] < traj.y[idx, traj.index(self.below)]
            ok &= under
            parts.append(f"below {self.below} at {np.mean(under):.0%}")
        share = float(np.mean(ok))
        return Outcome(desc, share >= self.min_fraction - 1e-9,
                       f"all bounds met at {share:.1%} of {len(idx)} samples ("
                       + "; ".join(parts) + ")")


class Expectation(Spec, kw_only=True, dict=True):
    x_at_end: XAtEnd | None = None
    height_at_end: HeightAtEnd | None = None
    tilt_never_above: TiltNeverAbove | None = None
    tilt_at_end: TiltAtEnd | None = None
    touching_at_end: TouchingAtEnd | None = None
    followed_channels: FollowedChannels | None = None
    upright_at_end: bool | None = None
    never_fell: bool | None = None
    reached_height: ReachedHeight | None = None
    airborne: Airborne | None = None
    turned: Turned | None = None
    landed_at: LandedAt | None = None
    took_off: TookOff | None = None
    first_touch: FirstTouch | None = None
    on_ground: OnGround | None = None
    angle_within: AngleWithin | None = None
    swung: Swung | None = None
    touched: Touched | None = None
    bent_after_flight: BentAfterFlight | None = None
    stood_on: StoodOn | None = None
    got_up: GotUp | None = None
    mean_speed: MeanSpeed | None = None
    flight_phases: FlightPhases | None = None
    run_up: RunUp | None = None
    balanced_on: BalancedOn | None = None
    stayed_in_state: StayedInState | str | None = None  # a name: the whole run
    stayed_in_mode: StayedInMode | str | None = None
    revolutions: Revolutions | None = None
    held: Held | None = None
    in_state_at_end: str | None = None
    in_mode_at_end: str | None = None
    held_point: HeldPoint | None = None
    always_holding: AlwaysHolding | None = None
    regrasps: Regrasps | None = None
    mostly_within: MostlyWithin | None = None
    final_hash: str | None = None
    # (Located, data path) of this entry, for errors found only when evaluating, is
    # set as ``_where`` (not a field: ``dict=True`` lets the struct hold it)

    def __post_init__(self):
        if isinstance(self.stayed_in_state, str):  # the shorthand stayed_in_state: NAME
            self.stayed_in_state = StayedInState(state=self.stayed_in_state)
        if isinstance(self.stayed_in_mode, str):
            self.stayed_in_mode = StayedInMode(mode=self.stayed_in_mode)
        given = [n for n in self.__struct_fields__ if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("each expectation names exactly one check; got "
                             f"{', '.join(given) or 'none'}")

    @property
    def kind(self) -> str:
        return next(n for n in self.__struct_fields__ if getattr(self, n) is not None)

    @property
    def value(self):
        return getattr(self, self.kind)

    def error(self, message: str, *sub) -> DataError:
        """A DataError at this entry (``sub``: a key inside it) if it came from a file."""
        where = getattr(self, "_where", None)
        if where is None:
            return DataError("expect", None, None, message)
        located, loc = where
        return located.error(loc + sub, message)

    def link(self) -> str | None:
        v = self.value
        return getattr(v, "link", None) if isinstance(v, Spec) else None

    def describe(self) -> str:
        v = self.value
        if isinstance(v, XAtEnd):
            what = "com" if v.com else v.link
            bounds = " ".join(f"{k} {b}" for k, b in (("min", v.min), ("max", v.max))
                              if b is not None)
            return f"x_at_end {what} {bounds}"
        if isinstance(v, HeightAtEnd):
            bounds = " ".join(f"{k} {b}" for k, b in (("min", v.min), ("max", v.max))
                              if b is not None)
            return f"height_at_end {v.link} {bounds}" + (f" held {v.held} s" if v.held else "")
        if isinstance(v, TiltNeverAbove):
            return f"tilt_never_above {', '.join(v.links)} max {v.max} deg"
        if isinstance(v, TiltAtEnd):
            return (f"tilt_at_end {', '.join(v.links)} max {v.max} deg"
                    + (f" held {v.held} s" if v.held else ""))
        if isinstance(v, TouchingAtEnd):
            share = f" at {v.min_fraction:g} of the samples" if v.min_fraction < 1 else ""
            return (f"touching_at_end {', '.join(v.links)}"
                    + (f" held {v.held} s{share}" if v.held else ""))
        if isinstance(v, ReachedHeight):
            return f"reached_height {v.link} min {v.min} m"
        if isinstance(v, FollowedChannels):
            until = "the end" if v.until is None else f"{v.until:g} s"
            bounds = " and ".join(b for b in (
                f"each within {v.max_rms:g}" if v.max_rms is not None else "",
                f"one at least {v.min_rms:g}" if v.min_rms is not None else "") if b)
            return (f"followed_channels {', '.join(v.joints)}: {bounds} deg RMS "
                    f"from {v.from_:g} s to {until}")
        if isinstance(v, Airborne):
            bounds = " ".join(f"{k} {b} s" for k, b in (("min", v.min_seconds),
                                                        ("max", v.max_seconds)) if b is not None)
            return f"airborne {v.link} {bounds}"
        if isinstance(v, StoodOn):
            return (f"stood_on {v.link} alone, root >= {v.min_tilt:g} deg from upright, "
                    f"min {v.min_seconds} s")
        if isinstance(v, BalancedOn):
            feet = f", {', '.join(v.above)} above {v.over}" if v.above else ""
            return (f"balanced_on {', '.join(v.links)} only, root >= {v.min_tilt:g} deg from "
                    f"upright{feet}, min {v.min_seconds} s")
        if isinstance(v, GotUp):
            return (f"got_up: lay (>= {v.min_tilt:g} deg) min {v.lay_seconds} s, up "
                    f"(<= {v.upright_tilt:g} deg) within {v.within_seconds} s")
        if isinstance(v, Turned):
            return (f"turned {v.link} {v.direction} min {v.min_degrees} deg"
                    + (" in flight" if v.in_flight else ""))
        if isinstance(v, LandedAt):
            return f"landed_at {v.link} min x {v.min} m"
        if isinstance(v, Revolutions):
            about = v.about if isinstance(v.about, str) else f"[{v.about[0]:g}, {v.about[1]:g}]"
            way = "" if v.direction == "either" else f" {v.direction}"
            return f"revolutions about {about}{way} min {v.min:g} in a row"
        if isinstance(v, Held):
            window = "".join(f" {k} {b} s" for k, b in (("from", v.from_), ("until", v.until))
                             if b is not None)
            on = f" on {v.prop}" if v.prop else ""
            return f"held {', '.join(v.chains)}{on}{window}"
        if isinstance(v, HeldPoint):
            return f"held_point {v.prop} {v.point}" + (f" by {v.chain}" if v.chain else "")
        if isinstance(v, AlwaysHolding):
            window = "".join(f" {k} {b} s" for k, b in (("from", v.from_), ("until", v.until))
                             if b is not None)
            return f"always_holding one of {', '.join(v.chains)}{window}"
        if isinstance(v, MostlyWithin):
            return v.describe()
        if isinstance(v, Regrasps):
            return (f"regrasps {', '.join(v.chains)} along {v.prop} min {v.min}"
                    + (" by turns" if v.alternate else ""))
        if isinstance(v, TookOff):
            return (f"took_off from {', '.join(v.links)} only"
                    + (f", each at x <= {v.max_x:g} m" if v.max_x is not None else "")
                    + (f", flight min {v.min_seconds:g} s" if v.min_seconds else ""))
        if isinstance(v, OnGround):
            tilt = _at_least_most(v.min_root_angle, v.max_root_angle)
            return (f"on_ground {', '.join(v.links)} min {v.min_seconds:g} s"
                    + (f", root {tilt} deg (signed)" if tilt else ""))
        if isinstance(v, Swung):
            return (f"swung min {v.min:g} deg each way about [{v.about[0]:g}, "
                    f"{v.about[1]:g}] from {v.from_:g} s to {_until(v)}")
        if isinstance(v, AngleWithin):
            bounds = _at_least_most(v.min, v.max)
            return (f"angle_within {v.link} {bounds} deg (signed) from {v.from_:g} s "
                    f"to {_until(v)}")
        if isinstance(v, Touched):
            return (f"touched with {', '.join(v.links)}, lowest point >= {v.min_height:g} m"
                    + (f", x >= {v.min_x:g} m" if v.min_x is not None else "")
                    + (", before the longest flight" if v.before_flight else ""))
        if isinstance(v, BentAfterFlight):
            bounds = _at_least_most(v.min, v.max)
            return (f"bent_after_flight {', '.join(v.links)} from {v.from_link} {bounds} "
                    f"deg within {v.within:g} s of the landing")
        if isinstance(v, FirstTouch):
            return (f"first_touch {', '.join(v.links)} only"
                    + (f", each at x >= {v.min_x:g} m" if v.min_x is not None else ""))
        if isinstance(v, MeanSpeed):
            bounds = " ".join(f"{k} {b}" for k, b in (("min", v.min), ("max", v.max))
                              if b is not None)
            return f"mean_speed {bounds} m/s from {v.from_:g} s to {_until(v)}"
        if isinstance(v, FlightPhases):
            what = "no link" if v.links is None else f"none of {', '.join(v.links)}"
            count = _at_least_most(v.min_count, v.max_count)
            return (f"flight_phases {count} of {v.min_seconds:g} s or more "
                    f"({what} touching) from {v.from_:g} s to {_until(v)}")
        if isinstance(v, RunUp):
            what = "no link" if v.links is None else f"none of {', '.join(v.links)}"
            parts = ([f"at least {v.min_flights} flights of {v.flight_seconds:g} s or more "
                      f"({what} touching)"
                      + (f" begun within {v.within:g} s of it" if v.within is not None
                         else "")] if v.min_flights else [])
            if v.min_speed is not None:
                parts.append(f"mean_speed min {v.min_speed:g} m/s over its last {v.over:g} s")
            return "run_up before the longest flight: " + ", ".join(parts)
        if isinstance(v, StayedIn):
            window = "".join(f" {k} {b} s" for k, b in (("from", v.from_), ("until", v.until))
                             if b is not None)
            return f"{self.kind} {v.name}{window}"
        return f"{self.kind} {v}".replace("True", "true").replace("False", "false")


class ExpectFile(Spec, kw_only=True):
    description: str = ""
    expect: list[Expectation]
    # how forgiving the feat must be: ``puppet playtest`` checks it (docs/interfaces.md)
    playtest: PlaytestBar | None = None


# (low, high) fields of a kind's settings: the high one may not be under the low one
# (an entry that nothing can pass); the YAML names (``from_`` is 'from')
BOUND_PAIRS = (("min", "max"), ("from_", "until"), ("x_min", "x_max"),
               ("min_seconds", "max_seconds"), ("min_rms", "max_rms"),
               ("min_root_angle", "max_root_angle"), ("min_count", "max_count"))


def _yaml_name(name: str) -> str:
    return name.removesuffix("_")


def _bounds_problem(v) -> tuple[str, str] | None:
    """(the high field's YAML name, the message) for a pair of bounds that no value can
    meet (max under min, until before from), checked once here for every kind."""
    for low, high in BOUND_PAIRS:
        lo, hi = getattr(v, low, None), getattr(v, high, None)
        if isinstance(lo, bool) or isinstance(hi, bool) or not (
                isinstance(lo, (int, float)) and isinstance(hi, (int, float))):
            continue
        if hi < lo:
            a, b = _yaml_name(low), _yaml_name(high)
            if low == "from_":
                return b, (f"'{b}' ({hi:g} s) is before '{a}' ({lo:g} s): the window is "
                           f"empty; expected '{b}' at or after '{a}'")
            return b, (f"'{b}' ({hi:g}) is less than '{a}' ({lo:g}): nothing can be in "
                       f"that range; expected '{b}' at least '{a}'")
    return None


@dataclass
class Expectations:
    """Validated expectations and where they came from (for errors about link names).
    ``notes``: what loading them would warn about (one line each: a header's entries
    left out for the sidecar's, an empty list)."""

    items: list[Expectation]
    located: Located | None
    loc_prefix: tuple  # data path of the list inside ``located``
    notes: list[str] = dc_field(default_factory=list)

    def __post_init__(self):
        if self.located is not None:
            for i, e in enumerate(self.items):
                e._where = (self.located, self.loc_prefix + (i, e.kind))
        for e in self.items:
            if isinstance(e.value, Spec) and (problem := _bounds_problem(e.value)):
                raise e.error(f"{e.kind}: {problem[1]}", problem[0])

    def check_names(self, names) -> None:
        """DataError (at the entry) for a state or mode the interface does not define:
        ``names`` has ``state_names`` and ``mode_names`` (a Trajectory, or what
        ``puppet check`` reads from the log's interface versions)."""
        for e in self.items:
            if isinstance(e.value, StayedIn):
                _check_name(e, names, e.value.column, e.value.name, e.value.column)
            elif e.kind in AT_END:
                _check_name(e, names, AT_END[e.kind], e.value)

    def check_windows(self, end: float) -> None:
        """DataError (at its 'from') for a window that begins after ``end`` (s: the
        log's last step), which no sample of the replay can be in."""
        for e in self.items:
            start = getattr(e.value, "from_", None) if isinstance(e.value, Spec) else None
            if start is not None and start > end + 1e-9:
                raise e.error(f"'from' ({start:g} s) is after the log's end ({end:.2f} s): "
                              f"no sample is in the window; expected 'from' at most "
                              f"{end:.2f} s", "from")

    def check_links(self, links: list[str]) -> None:
        """DataError (at the entry) for a link the character does not have."""
        for e in self.items:
            named = getattr(e.value, "links", None) if isinstance(e.value, Spec) else None
            for i, name in enumerate(named if named is not None else
                                     ([e.link()] if e.link() is not None else [])):
                if name not in links:
                    raise e.error(f"unknown link '{name}'; the character has: "
                                  f"{', '.join(links)}", *(("links", i) if named else ("link",)))


def sidecar_path(log_path: str | Path) -> Path:
    """``NAME.expect.yaml`` next to ``NAME.jsonl`` (``NAME.jsonl.expect.yaml`` also works)."""
    p = Path(log_path)
    plain = p.with_name(p.name.removesuffix(".jsonl") + ".expect.yaml")
    if not plain.is_file():
        other = p.with_name(p.name + ".expect.yaml")
        if other.is_file():
            return other
    return plain


def _one_check_each(located: Located) -> None:
    """An entry naming two checks (or none) of the known kinds, refused in one line at
    the entry (msgspec's words would add the entry as a cut Python dict)."""
    items = located.data.get("expect") if isinstance(located.data, dict) else None
    if not isinstance(items, list):
        return
    kinds = Expectation.__struct_fields__
    for i, entry in enumerate(items):
        if not isinstance(entry, dict) or any(k not in kinds for k in entry):
            continue  # not a mapping, or an unknown key: validate says what is wrong
        if len(entry) != 1:
            named = (f"names {len(entry)}: {', '.join(map(str, entry))}" if entry
                     else "names none")
            raise located.error(("expect", i), f"each expectation names exactly one check; "
                                               f"this entry {named} (expected one per '- ' "
                                               f"entry)")


def validate_expect_file(located: Located) -> ExpectFile:
    """A sidecar file's (or the header's) ``expect:`` list validated: each entry one
    check, every pair of bounds one that a value can meet."""
    _one_check_each(located)
    spec = validate(located, ExpectFile)
    Expectations(spec.expect, located, ("expect",))  # the bounds, at their entries
    return spec


def load_expectations(log_path: str | Path, header: dict) -> Expectations:
    """The sidecar file's expectations if there is one, else the header's: the sidecar
    wins, and a header's own entries then left out are a note; so is an empty list
    (a replay --check that checks nothing but the end state)."""
    side = sidecar_path(log_path)
    if side.is_file():
        located = load_file(side)
        spec = validate_expect_file(located)
        result = Expectations(spec.expect, located, ("expect",))
        if header.get("expect"):
            result.notes.append(f"{log_path}: warning: the header's {len(header['expect'])} "
                                f"expectation(s) are not checked: the sidecar {side.name} "
                                f"replaces them (the sidecar wins)")
    else:
        raw = header.get("expect") or []
        located = Located(str(log_path), {"expect": raw}, value_pos={(): (1, 1)})
        spec = validate_expect_file(located)
        result = Expectations(spec.expect, located, ("expect",))
        side = None
    if not spec.expect and (side is not None or "expect" in header):
        result.notes.append(f"{side or log_path}: warning: 'expect' is an empty list: "
                            "no expectation is checked")
    return result


def parse_expectations(items: list, where: str = "expect") -> Expectations:
    """Expectations given as Python data (e.g. by a test): a list of entries."""
    if not isinstance(items, (list, tuple)):
        raise DataError(where, None, None, f"expected a list of expectation entries "
                                           f"(e.g. [{{'never_fell': True}}]), got "
                                           f"{type(items).__name__} {_short(items)}")
    located = Located(where, {"expect": list(items)})
    return Expectations(validate_expect_file(located).expect, located, ("expect",))


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


# -- evaluation ------------------------------------------------------------------------
@dataclass
class Outcome:
    expectation: str  # what was expected, one line
    passed: bool
    measured: str  # what was measured, one line
    # the expectation's kind (its key: 'never_fell', 'flight_phases'...; 'same_end' for
    # the recorded end state a closed log adds)
    kind: str = ""

    def __str__(self) -> str:
        return f"{'ok  ' if self.passed else 'FAIL'} {self.expectation}: {self.measured}"


def _tilt_deg(angle: np.ndarray) -> np.ndarray:
    return np.abs(np.degrees(np.remainder(angle + np.pi, 2 * np.pi) - np.pi))


def _runs(flags: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) sample index of each stretch of consecutive true samples: the
    flights (or times out of contact) that airborne, turned and landed_at measure."""
    edges = np.diff(np.concatenate(([0], np.asarray(flags, dtype=np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1).tolist(),
                    (np.flatnonzero(edges == -1) - 1).tolist()))


def _at_least_most(low: float | None, high: float | None) -> str:
    """"at least LOW and at most HIGH" (either left out when None), as bounds are said."""
    return " and ".join(f"{w} {b:g}" for w, b in (("at least", low), ("at most", high))
                        if b is not None)


def _longest_run(flags: np.ndarray, t: np.ndarray) -> tuple[float, int, int]:
    """Longest (first if tied) stretch of true samples: (seconds, first, last index);
    (0.0, -1, -1) if there is none. Longest by its number of samples, which ties
    exactly: the seconds (t[last] - t[first] + the median interval) of two equally long
    stretches differ in the last bit by where they are in the run, and the later one
    would win by rounding."""
    best, count = (0.0, -1, -1), 0
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    for i, j in _runs(flags):
        if j - i + 1 > count:
            best, count = (float(t[j] - t[i] + dt), i, j), j - i + 1
    return best


def _named(x) -> str:
    """A state or mode for a message; none for an interface (version) without them."""
    return "none" if x is None else f"'{x}'"


def _check_name(e: Expectation, traj, column: str, name: str, *sub) -> None:
    """DataError (at the entry) for a state or mode the interface does not define."""
    names = getattr(traj, f"{column}_names")
    if name not in names:
        have = (f"the interface has: {', '.join(names)}" if names
                else f"the interface has no {column}s")
        raise e.error(f"unknown {column} '{name}'; {have}", *sub)


def _samples_in(t: np.ndarray, start: float | None, end: float | None) -> np.ndarray:
    """The indices of the samples from ``start`` to ``end`` (s, both included; None:
    the run's start or end)."""
    lo = -np.inf if start is None else start - 1e-9
    hi = np.inf if end is None else end + 1e-9
    return np.flatnonzero((t >= lo) & (t <= hi))


def _no_samples(desc: str, t: np.ndarray) -> Outcome:
    return Outcome(desc, False, f"no samples in the window (the run is {t[-1]:.2f} s)")


def _stayed(e: Expectation, v: StayedIn, traj) -> Outcome:
    """In the state (or mode) at every sample of the window; else where it first was
    not: the state it left for, or the one it was in when the window began."""
    _check_name(e, traj, v.column, v.name, v.column)  # at the name (shorthand: the entry)
    t, seen = traj.t, getattr(traj, v.column)
    idx = _samples_in(t, v.from_, v.until)
    if len(idx) == 0:
        return _no_samples(e.describe(), t)
    off = idx[seen[idx] != v.name]
    if len(off) == 0:
        return Outcome(e.describe(), True, f"in '{v.name}' from t = {t[idx[0]]:.2f} s "
                                           f"to {t[idx[-1]]:.2f} s")
    k = int(off[0])
    if k == idx[0]:
        what = f"in {_named(seen[k])}, not '{v.name}', at t = {t[k]:.2f} s"
    else:
        what = f"left '{v.name}' for {_named(seen[k])} at t = {t[k]:.2f} s"
    return Outcome(e.describe(), False, what)


def _got_up(desc: str, v: GotUp, traj) -> Outcome:
    """The last stretch lying (root >= min_tilt from upright while touching), at least
    lay_seconds long; then standing (root <= upright_tilt) from some sample to the end,
    reached within within_seconds of the end of lying."""
    tilt = _tilt_deg(traj.root_angle)
    lying = (tilt >= v.min_tilt) & traj.contact.any(axis=1)
    runs = _runs(lying)
    if not runs:
        return Outcome(desc, False, f"never lay (root >= {v.min_tilt:g} deg on the ground)")
    dt = float(np.median(np.diff(traj.t))) if len(traj.t) > 1 else 0.0
    i, j = runs[-1]
    lay = float(traj.t[j] - traj.t[i] + dt)
    up = tilt <= v.upright_tilt
    after = np.flatnonzero(~up)
    first_up = (int(after[-1]) + 1) if len(after) else 0  # standing from here to the end
    if first_up >= len(up) or first_up <= j:
        return Outcome(desc, False, f"lay {lay:.2f} s until t = {traj.t[j]:.2f} s, "
                                    f"not standing at the end ({tilt[-1]:.0f} deg)")
    took = float(traj.t[first_up] - traj.t[j])
    ok = lay >= v.lay_seconds - 1e-9 and took <= v.within_seconds + 1e-9
    return Outcome(desc, ok, f"lay {lay:.2f} s (t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s), "
                             f"standing from t = {traj.t[first_up]:.2f} s: up in {took:.2f} s")


def _balanced_on(e: Expectation, v: BalancedOn, traj) -> Outcome:
    """The longest stretch where some of ``links`` touch and nothing else, the root is
    tilted at least min_tilt and every ``above`` link is higher than ``over``."""
    for i, name in enumerate(v.above + ([v.over] if v.over else [])):
        if name not in traj.links:
            sub = ("above", i) if i < len(v.above) else ("over",)
            raise e.error(f"unknown link '{name}'; the character has: "
                          f"{', '.join(traj.links)}", *sub)
    k = [traj.index(n) for n in v.links]
    on = (traj.contact[:, k].any(axis=1) & ~np.delete(traj.contact, k, axis=1).any(axis=1)
          & (_tilt_deg(traj.root_angle) >= v.min_tilt))
    for name in v.above:
        on &= traj.y[:, traj.index(name)] > traj.y[:, traj.index(v.over)]
    length, i, j = _longest_run(on, traj.t)
    return Outcome(e.describe(), length > 0 and length >= v.min_seconds - 1e-9,
                   f"longest stretch on {', '.join(v.links)} alone, upside down: {length:.3f} s"
                   + (f" (t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s)" if length > 0 else ""))


def _followed(e: Expectation, v: FollowedChannels, traj) -> Outcome:
    window = (traj.t >= v.from_ - 1e-9) & (traj.t <= (np.inf if v.until is None
                                                     else v.until + 1e-9))
    worst, which, parts = -1.0, v.joints[0], []
    for name in v.joints:
        if name not in traj.joints:
            raise e.error(f"no joint named '{name}' in this character (joints: "
                          f"{', '.join(traj.joints)})", "joints")
        k = traj.joints.index(name)
        have = window & ~np.isnan(traj.joint_channel[:, k])
        if not have.any():
            return Outcome(e.describe(), False, f"no channel '{name}' came in the window")
        diff = np.degrees(np.remainder(traj.joint_angle[have, k] - traj.joint_channel[have, k]
                                       + np.pi, 2 * np.pi) - np.pi)
        rms = float(np.sqrt(np.mean(diff ** 2)))
        parts.append(f"{name} {rms:.1f}")
        if rms > worst:
            worst, which = rms, name
    ok = (v.max_rms is None or worst <= v.max_rms) and (v.min_rms is None
                                                        or worst >= v.min_rms)
    return Outcome(e.describe(), ok, f"RMS deg: {', '.join(parts)} (worst {which})")


def _until(v) -> str:
    return "the end" if v.until is None else f"{v.until:g} s"


def _swung(desc: str, v: Swung, traj) -> Outcome:
    """The centre of mass's angle about the point over the window: both extremes."""
    idx = _samples_in(traj.t, v.from_, v.until)
    if len(idx) == 0:
        return _no_samples(desc, traj.t)
    dx = traj.com[idx, 0] - v.about[0]
    dy = traj.com[idx, 1] - v.about[1]
    angle = np.degrees(np.arctan2(dx, -dy))
    lo, hi = float(angle.min()), float(angle.max())
    return Outcome(desc, hi >= v.min - 1e-9 and -lo >= v.min - 1e-9,
                   f"{lo:.1f}..{hi:.1f} deg from t = {traj.t[idx[0]]:.2f} to "
                   f"{traj.t[idx[-1]]:.2f} s")


def _angle_within(desc: str, v: AngleWithin, traj) -> Outcome:
    """The samples of the window whose signed angle is out of bounds: the first of them
    and the range the angle took."""
    idx = _samples_in(traj.t, v.from_, v.until)
    if len(idx) == 0:
        return _no_samples(desc, traj.t)
    # in (top - 360, top]: -180..180, or across upside down when max is over 180
    top = 180.0 if v.max is None or v.max <= 180 else v.max
    angle = top - np.remainder(top - np.degrees(traj.angle[idx, traj.index(v.link)]), 360.0)
    out = np.zeros(len(idx), dtype=bool)
    if v.min is not None:
        out |= angle < v.min
    if v.max is not None:
        out |= angle > v.max
    span = (f"{v.link} {angle.min():.0f}..{angle.max():.0f} deg from t = "
            f"{traj.t[idx[0]]:.2f} to {traj.t[idx[-1]]:.2f} s")
    if not out.any():
        return Outcome(desc, True, span)
    k = int(np.flatnonzero(out)[0])
    return Outcome(desc, False, f"{span}; out at t = {traj.t[idx[k]]:.2f} s "
                                f"({angle[k]:.0f} deg)")


def _mean_speed(desc: str, v: MeanSpeed, traj) -> Outcome:
    idx = _samples_in(traj.t, v.from_, v.until)
    if len(idx) < 2 or traj.t[idx[-1]] <= traj.t[idx[0]]:
        return Outcome(desc, False, f"fewer than two samples in the window (the run is "
                                    f"{traj.t[-1]:.2f} s)")
    i, j = int(idx[0]), int(idx[-1])
    speed = float((traj.com[j, 0] - traj.com[i, 0]) / (traj.t[j] - traj.t[i]))
    ok = (v.min is None or speed >= v.min) and (v.max is None or speed <= v.max)
    return Outcome(desc, ok, f"{speed:.3f} m/s (x {traj.com[i, 0]:.2f} to "
                             f"{traj.com[j, 0]:.2f} m, t = {traj.t[i]:.2f} to "
                             f"{traj.t[j]:.2f} s)")


def _flight_phases(e: Expectation, v: FlightPhases, traj) -> Outcome:
    names = traj.links if v.links is None else v.links
    for k, name in enumerate(names):
        if name not in traj.links:
            raise e.error(f"unknown link '{name}'; the character has: "
                          f"{', '.join(traj.links)}", "links", k)
    cols = [traj.index(n) for n in names]
    free = ~traj.contact[:, cols].any(axis=1)
    hi = np.inf if v.until is None else v.until + 1e-9
    lengths = []
    for i, j in _runs(free):
        if not (v.from_ - 1e-9 <= traj.t[i] <= hi):
            continue
        end = traj.t[j + 1] if j + 1 < len(traj.t) else traj.t[j]  # first sample down
        lengths.append(float(end - traj.t[i]))
    long = [d for d in lengths if d >= v.min_seconds - 1e-9]
    longest = f", the longest {max(lengths):.3f} s" if lengths else ""
    ok = ((v.min_count is None or len(long) >= v.min_count)
          and (v.max_count is None or len(long) <= v.max_count))
    return Outcome(e.describe(), ok,
                   f"{len(long)} flights of {v.min_seconds:g} s or more "
                   f"({len(lengths)} in all{longest})")


def _run_up(e: Expectation, v: RunUp, traj) -> Outcome:
    names = traj.links if v.links is None else v.links
    for k, name in enumerate(names):
        if name not in traj.links:
            raise e.error(f"unknown link '{name}'; the character has: "
                          f"{', '.join(traj.links)}", "links", k)
    length, jump, _ = _longest_run(~traj.contact.any(axis=1), traj.t)
    if length <= 0:
        return Outcome(e.describe(), False, "never in the air")
    start = float(traj.t[jump])
    free = ~traj.contact[:, [traj.index(n) for n in names]].any(axis=1)
    flights = []
    for i, j in _runs(free[:jump]):
        if j + 1 >= jump:  # still off the ground when the jump began: part of it
            continue
        if v.within is not None and traj.t[i] < start - v.within - 1e-9:
            continue
        if traj.t[j + 1] - traj.t[i] >= v.flight_seconds - 1e-9:
            flights.append(float(traj.t[i]))
    ok = len(flights) >= v.min_flights
    said = [f"the jump from t = {start:.2f} s; {len(flights)} flights of "
            f"{v.flight_seconds:g} s or more before it"]
    if v.min_speed is not None:
        if start - float(traj.t[0]) < v.over - 1e-9:
            return Outcome(e.describe(), False, said[0] + f"; the jump began {start:.2f} s "
                           f"into the run, less than {v.over:g} s")
        idx = _samples_in(traj.t, start - v.over, start)
        if len(idx) < 2 or traj.t[idx[-1]] <= traj.t[idx[0]]:
            return Outcome(e.describe(), False, said[0] + f"; fewer than two samples in the "
                           f"{v.over:g} s before the jump")
        i, j = int(idx[0]), int(idx[-1])
        speed = float((traj.com[j, 0] - traj.com[i, 0]) / (traj.t[j] - traj.t[i]))
        ok = ok and speed >= v.min_speed
        said.append(f"{speed:.3f} m/s over t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s")
    return Outcome(e.describe(), ok, "; ".join(said))


def _at_end(e: Expectation, column: str, traj) -> Outcome:
    _check_name(e, traj, column, e.value)
    seen = getattr(traj, column)
    changed = np.flatnonzero(seen != seen[-1])
    since = traj.t[changed[-1] + 1] if len(changed) else traj.t[0]
    return Outcome(e.describe(), seen[-1] == e.value,
                   f"in {_named(seen[-1])} at the end (since t = {since:.2f} s)")


def _held_at(traj, chain: str) -> list:
    """Per sample: (x, y, prop) of what ``chain`` held, or None."""
    out = []
    for row in _holds(traj):
        out.append(next(((x, y, prop) for name, prop, _, x, y in row if name == chain), None))
    return out


def _revolutions(e: Expectation, v: Revolutions, traj) -> Outcome:
    """The unwrapped angle of the centre of mass about the point; the longest stretch
    that never turns back more than ``slack`` degrees from its furthest; its turn /
    360. About a chain: only samples where it holds count (a release ends a stretch)."""
    n = len(traj.t)
    if isinstance(v.about, str):
        at = _held_at(traj, v.about)
        if all(a is None for a in at):
            return Outcome(e.describe(), False, f"'{v.about}' never held anything (a chain "
                                                "of the interface that grasps?)")
    else:
        at = [(v.about[0], v.about[1], None)] * n
    best, where = 0.0, ""
    ways = {"backward": (1.0,), "forward": (-1.0,), "either": (1.0, -1.0)}[v.direction]
    slack = np.radians(v.slack)
    for sign in ways:
        prev = start = top = None
        i0 = 0
        for i in range(n):
            if at[i] is None:
                prev = None
                continue
            a = float(np.arctan2(traj.com[i, 1] - at[i][1], traj.com[i, 0] - at[i][0]))
            if prev is None:
                u = a
                start = top = sign * u
                i0 = i
            else:
                u = prev_u + (np.remainder(a - prev + np.pi, 2 * np.pi) - np.pi)
            prev, prev_u = a, u
            s = sign * u
            if s > top:
                top = s
            elif s < top - slack:  # turned back: a new stretch from here
                start = top = s
                i0 = i
            turns = (top - start) / (2 * np.pi)
            if turns > best:
                best = turns
                way = "backward" if sign > 0 else "forward"
                where = f" {way}, from t = {traj.t[i0]:.2f} s to {traj.t[i]:.2f} s"
    return Outcome(e.describe(), best >= v.min - 1e-9, f"{best:.2f} turns in a row{where}")


def _held(e: Expectation, v: Held, traj) -> Outcome:
    t = traj.t
    idx = _samples_in(t, v.from_, v.until)
    if len(idx) == 0:
        return _no_samples(e.describe(), t)
    for chain in v.chains:
        at = _held_at(traj, chain)
        if all(a is None for a in at):
            return Outcome(e.describe(), False, f"{chain} never held anything (a chain of "
                                                "the interface that grasps?)")
        for i in idx:
            if at[i] is None or (v.prop is not None and at[i][2] != v.prop):
                what = "nothing" if at[i] is None else (at[i][2] or "the world")
                return Outcome(e.describe(), False,
                               f"{chain} held {what} at t = {t[i]:.2f} s")
    return Outcome(e.describe(), True, f"all held from t = {t[idx[0]]:.2f} s to "
                                       f"{t[idx[-1]]:.2f} s")
def _flight_end(desc: str, v: TookOff | FirstTouch, traj) -> Outcome:
    """took_off (the sample before the longest flight) or first_touch (the one after
    it): which links touched there and where; the flight's length for took_off."""
    free = ~traj.contact.any(axis=1)
    length, first, last = _longest_run(free, traj.t)
    if length <= 0:
        return Outcome(desc, False, "never in the air")
    i = first - 1 if isinstance(v, TookOff) else last + 1
    if i < 0 or i >= len(free):
        return Outcome(desc, False, f"the longest flight ({length:.2f} s) "
                                    + ("began" if i < 0 else "had not ended")
                                    + " within the run")
    touching = [n for k, n in enumerate(traj.links) if traj.contact[i, k]]
    where = ", ".join(f"{n} at x = {traj.x[i, traj.index(n)]:.3f}" for n in touching)
    others = [n for n in touching if n not in v.links]
    ok = not others
    if isinstance(v, TookOff):
        ok = ok and length >= v.min_seconds - 1e-9 and (
            v.max_x is None or all(traj.x[i, traj.index(n)] <= v.max_x for n in touching))
        return Outcome(desc, ok, f"longest flight {length:.2f} s from t = "
                                 f"{traj.t[first]:.2f} s; on the ground before it: {where}")
    ok = ok and (v.min_x is None
                 or all(traj.x[i, traj.index(n)] >= v.min_x for n in touching))
    return Outcome(desc, ok, f"longest flight {length:.2f} s ended at t = {traj.t[i]:.2f} s; "
                             f"touching first: {where}")


def evaluate(e: Expectation, traj, final_hash: str) -> Outcome:
    """Check one expectation against a sampled trajectory (see ``Trajectory``)."""
    outcome = _evaluate(e, traj, final_hash)
    outcome.kind = e.kind
    return outcome


def _evaluate(e: Expectation, traj, final_hash: str) -> Outcome:
    v, desc = e.value, e.describe()
    if isinstance(v, XAtEnd):
        x = float(traj.com[-1, 0]) if v.com else float(traj.x[-1, traj.index(v.link)])
        ok = (v.min is None or x >= v.min) and (v.max is None or x <= v.max)
        return Outcome(desc, ok, f"x = {x:.3f} m at t = {traj.t[-1]:.2f} s")
    if isinstance(v, HeightAtEnd):
        y = traj.y[:, traj.index(v.link)]
        window = y[traj.t >= traj.t[-1] - v.held - 1e-9]
        lo, hi = float(window.min()), float(window.max())
        ok = (v.min is None or lo >= v.min) and (v.max is None or hi <= v.max)
        return Outcome(desc, ok, f"y = {lo:.3f}..{hi:.3f} m over the last {v.held:g} s"
                       if v.held else f"y = {lo:.3f} m at t = {traj.t[-1]:.2f} s")
    if isinstance(v, TiltNeverAbove):
        worst, at, which = -1.0, 0, v.links[0]
        for name in v.links:
            tilt = _tilt_deg(traj.angle[:, traj.index(name)])
            i = int(np.argmax(tilt))
            if tilt[i] > worst:
                worst, at, which = float(tilt[i]), i, name
        return Outcome(desc, worst <= v.max, f"{which} {worst:.0f} deg from upright at "
                                             f"t = {traj.t[at]:.2f} s (the most)")
    if isinstance(v, TiltAtEnd):
        window = traj.t >= traj.t[-1] - v.held - 1e-9
        worst, which = -1.0, v.links[0]
        for name in v.links:
            tilt = float(_tilt_deg(traj.angle[window, traj.index(name)]).max())
            if tilt > worst:
                worst, which = tilt, name
        return Outcome(desc, worst <= v.max, f"{which} at most {worst:.1f} deg from upright "
                       + (f"over the last {v.held:g} s" if v.held else "at the end"))
    if isinstance(v, TouchingAtEnd):
        window = traj.t >= traj.t[-1] - v.held - 1e-9
        shares = {name: float(traj.contact[window, traj.index(name)].mean())
                  for name in v.links}
        least = min(shares, key=shares.get)
        return Outcome(desc, shares[least] >= v.min_fraction - 1e-9,
                       f"{least} touching at {shares[least]:.0%} of the samples "
                       + (f"of the last {v.held:g} s" if v.held else "at the end")
                       + " (the least)")
    if isinstance(v, FollowedChannels):
        return _followed(e, v, traj)
    if e.kind == "upright_at_end":
        tilt = float(_tilt_deg(traj.root_angle[-1:])[0])
        upright = tilt <= UPRIGHT_DEG
        return Outcome(desc, upright == v, f"root {tilt:.0f} deg from upright at the end")
    if e.kind == "never_fell":
        tilt = np.where(traj.contact.any(axis=1), _tilt_deg(traj.root_angle), 0.0)
        i = int(np.argmax(tilt))
        fell = bool(tilt[i] > FELL_DEG)
        return Outcome(desc, (not fell) == v, f"largest tilt on the ground {tilt[i]:.0f} deg "
                                              f"at t = {traj.t[i]:.2f} s")
    if isinstance(v, ReachedHeight):
        low = traj.lowest[:, traj.index(v.link)]
        rise = low - low[0]
        i = int(np.argmax(rise))
        return Outcome(desc, bool(rise[i] >= v.min),
                       f"rose {rise[i]:.3f} m (at t = {traj.t[i]:.2f} s)")
    if isinstance(v, Airborne):
        free = ~traj.contact[:, traj.index(v.link)]
        length, i, _ = _longest_run(free, traj.t)
        ok = ((v.min_seconds is None or length >= v.min_seconds - 1e-9)
              and (v.max_seconds is None or length <= v.max_seconds + 1e-9))
        return Outcome(desc, ok, f"longest time out of contact {length:.3f} s"
                       + (f" (from t = {traj.t[i]:.2f} s)" if length > 0 else ""))
    if isinstance(v, StoodOn):
        k = traj.index(v.link)
        others = np.delete(traj.contact, k, axis=1).any(axis=1)
        on = traj.contact[:, k] & ~others & (_tilt_deg(traj.root_angle) >= v.min_tilt)
        length, i, j = _longest_run(on, traj.t)
        return Outcome(desc, length >= v.min_seconds - 1e-9 and length > 0,
                       f"longest stretch on {v.link} alone, upside down: {length:.3f} s"
                       + (f" (t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s)" if length > 0 else ""))
    if isinstance(v, GotUp):
        return _got_up(desc, v, traj)
    if isinstance(v, BalancedOn):
        return _balanced_on(e, v, traj)
    if isinstance(v, Turned):
        sign = 1.0 if v.direction == "backward" else -1.0
        turn = sign * np.degrees(np.unwrap(traj.angle[:, traj.index(v.link)]))
        where = ""
        if v.in_flight:
            free = ~traj.contact.any(axis=1)
            best, best_t0 = 0.0, None
            for i, j in _runs(free):
                # from the last sample on the ground before to the first after
                a, b = max(i - 1, 0), min(j + 1, len(free) - 1)
                if turn[b] - turn[a] > best:
                    best, best_t0 = float(turn[b] - turn[a]), float(traj.t[a])
            amount = best
            if best_t0 is not None:
                where = f" in the flight from t = {best_t0:.2f} s"
        else:
            amount = float(turn[-1] - turn[0])
        return Outcome(desc, amount >= v.min_degrees,
                       f"turned {amount:.0f} deg {v.direction}{where}")
    if isinstance(v, LandedAt):
        free = ~traj.contact.any(axis=1)
        length, first, last = _longest_run(free, traj.t)
        if length <= 0:
            return Outcome(desc, False, "never in the air")
        i = min(last + 1, len(free) - 1)  # the first sample touching again (or the last)
        x = float(traj.x[i, traj.index(v.link)])
        return Outcome(desc, x >= v.min, f"longest flight {length:.2f} s from t = "
                                         f"{traj.t[first]:.2f} s, "
                                         f"touched down at x = {x:.3f} m (t = {traj.t[i]:.2f} s)")
    if isinstance(v, Revolutions):
        return _revolutions(e, v, traj)
    if isinstance(v, Held):
        return _held(e, v, traj)
    if isinstance(v, (TookOff, FirstTouch)):
        return _flight_end(desc, v, traj)
    if isinstance(v, OnGround):
        angle = np.degrees(np.remainder(traj.root_angle + np.pi, 2 * np.pi) - np.pi)
        on = traj.contact[:, [traj.index(n) for n in v.links]].all(axis=1)
        if v.min_root_angle is not None:
            on &= angle >= v.min_root_angle
        if v.max_root_angle is not None:
            on &= angle <= v.max_root_angle
        length, i, j = _longest_run(on, traj.t)
        return Outcome(desc, length > 0 and length >= v.min_seconds - 1e-9,
                       f"longest stretch: {length:.2f} s"
                       + (f" (t = {traj.t[i]:.2f} to {traj.t[j]:.2f} s, root "
                          f"{angle[i:j + 1].min():.0f}..{angle[i:j + 1].max():.0f} deg)"
                          if length > 0 else ""))
    if isinstance(v, AngleWithin):
        return _angle_within(desc, v, traj)
    if isinstance(v, Swung):
        return _swung(desc, v, traj)
    if isinstance(v, Touched):
        return _touched(desc, v, traj)
    if isinstance(v, MeanSpeed):
        return _mean_speed(desc, v, traj)
    if isinstance(v, BentAfterFlight):
        return _bent_after_flight(e, v, traj)
    if isinstance(v, FlightPhases):
        return _flight_phases(e, v, traj)
    if isinstance(v, RunUp):
        return _run_up(e, v, traj)
    if isinstance(v, StayedIn):
        return _stayed(e, v, traj)
    if e.kind in AT_END:
        return _at_end(e, AT_END[e.kind], traj)
    if isinstance(v, HeldPoint):
        return _held_point(desc, v, traj)
    if isinstance(v, AlwaysHolding):
        return _always_holding(desc, v, traj)
    if isinstance(v, Regrasps):
        return _regrasps(desc, v, traj)
    if isinstance(v, MostlyWithin):
        return v.evaluate(e, traj)
    if e.kind == "final_hash":
        return Outcome(desc, final_hash == v, f"final hash {final_hash}")
    raise AssertionError(e.kind)


def _holds(traj) -> list[tuple]:
    """What the chains hold at each sample (``Trajectory.held``; () for none)."""
    return list(traj.held) if traj.held is not None else [()] * len(traj.t)


def _held_point(desc: str, v: HeldPoint, traj) -> Outcome:
    for i, held in enumerate(_holds(traj)):
        for chain, prop, point, *_ in held:
            if prop == v.prop and point == v.point and v.chain in (None, chain):
                return Outcome(desc, True, f"{chain} held it at t = {traj.t[i]:.2f} s")
    seen = sorted({p for held in _holds(traj) for c, pr, p, *_ in held
                   if pr == v.prop and p is not None and v.chain in (None, c)})
    return Outcome(desc, False, "never held; held " + (", ".join(seen) or "none of its points"))


def _always_holding(desc: str, v: AlwaysHolding, traj) -> Outcome:
    chains = set(v.chains)
    idx = _samples_in(traj.t, v.from_, v.until).tolist()
    if not idx:
        return _no_samples(desc, traj.t)
    holds = _holds(traj)
    for i in idx:
        if not any(chain in chains for chain, *_ in holds[i]):
            return Outcome(desc, False, f"none of them held anything at t = {traj.t[i]:.2f} s")
    return Outcome(desc, True, f"held on from t = {traj.t[idx[0]]:.2f} s to "
                               f"{traj.t[idx[-1]]:.2f} s")


def _regrasps(desc: str, v: Regrasps, traj) -> Outcome:
    """The progressing grasps (chain, point, t): the first point any of the chains
    holds is where they start; a new grasp of a point later in the prop's list than
    any held so far is one. Then the longest row of them (by turns if ``alternate``)."""
    chains = set(v.chains)
    names = (traj.prop_points or {}).get(v.prop)
    if names is None:
        return Outcome(desc, False, f"no prop '{v.prop}' in the scene")
    order = {n: k for k, n in enumerate(names)}
    best = None  # the furthest place held so far
    moves: list[tuple[str, str, float]] = []
    before: dict[str, str | None] = {}
    for i, held in enumerate(_holds(traj)):
        now = {c: p for c, pr, p, *_ in held if c in chains and pr == v.prop and p in order}
        for chain, point in sorted(now.items()):
            k = order[point]
            if best is None:
                best = k
            elif before.get(chain) != point and k > best:
                moves.append((chain, point, float(traj.t[i])))
                best = k
        before = now
    longest: list = []
    current: list = []
    for m in moves:
        if v.alternate and current and m[0] == current[-1][0]:
            current = [m]
        else:
            current.append(m)
        if len(current) > len(longest):
            longest = list(current)
    what = ", ".join(f"{c} {p} at {t:.2f} s" for c, p, t in longest[:12])
    return Outcome(desc, len(longest) >= v.min, f"{len(longest)} progressing grasps"
                   + (" by turns" if v.alternate else "") + (f": {what}" if what else ""))


def _touched(desc: str, v: Touched, traj) -> Outcome:
    """The first sample where one of the links touches that high (and that far on)."""
    window = np.ones(len(traj.t), dtype=bool)
    if v.before_flight:
        length, first, _ = _longest_run(~traj.contact.any(axis=1), traj.t)
        if length <= 0:
            return Outcome(desc, False, "no flight (nothing touching) to touch before")
        window[first:] = False
    for name in v.links:
        k = traj.index(name)
        hit = window & traj.contact[:, k] & (traj.lowest[:, k] >= v.min_height - 1e-9)
        if v.min_x is not None:
            hit &= traj.x[:, k] >= v.min_x - 1e-9
        if hit.any():
            i = int(np.argmax(hit))
            return Outcome(desc, True, f"{name} touched at t = {traj.t[i]:.2f} s, lowest "
                                       f"point {traj.lowest[i, k]:.3f} m up, x = "
                                       f"{traj.x[i, k]:.3f} m")
    up = [float(traj.lowest[window & traj.contact[:, traj.index(n)], traj.index(n)]
                .max(initial=-1)) for n in v.links]
    best = max(up)
    return Outcome(desc, False, "never touched that high" + (
        f" (highest touch {best:.3f} m up)" if best > -1 else " (never touched)"))



def _bent_after_flight(e: Expectation, v: BentAfterFlight, traj) -> Outcome:
    """The first sample after the longest flight, within ``within`` s of its end, with
    every link in range; else each link's range over that window."""
    for name, sub in [(n, ("links", k)) for k, n in enumerate(v.links)] + [
            (v.from_link, ("from_link",))]:
        if name not in traj.links:
            raise e.error(f"unknown link '{name}'; the character has: "
                          f"{', '.join(traj.links)}", *sub)
    desc = e.describe()
    length, first, last = _longest_run(~traj.contact.any(axis=1), traj.t)
    if length <= 0:
        return Outcome(desc, False, "never in the air")
    i = last + 1
    if i >= len(traj.t):
        return Outcome(desc, False, f"the longest flight ({length:.2f} s) had not ended "
                                    "within the run")
    window = np.arange(i, len(traj.t))[traj.t[i:] <= traj.t[i] + v.within + 1e-9]
    base = traj.angle[window, traj.index(v.from_link)]
    bend = np.stack([np.degrees(np.remainder(traj.angle[window, traj.index(n)] - base
                                             + np.pi, 2 * np.pi) - np.pi)
                     for n in v.links], axis=1)
    ok = np.ones(len(window), dtype=bool)
    if v.min is not None:
        ok &= (bend >= v.min - 1e-9).all(axis=1)
    if v.max is not None:
        ok &= (bend <= v.max + 1e-9).all(axis=1)
    spans = ", ".join(f"{n} {bend[:, k].min():.0f}..{bend[:, k].max():.0f}"
                      for k, n in enumerate(v.links))
    where = (f"the flight ended at t = {traj.t[i]:.2f} s; from {v.from_link}: {spans} deg "
             f"to t = {traj.t[window[-1]]:.2f} s")
    if ok.any():
        return Outcome(desc, True, f"{where}; in range at t = "
                                   f"{traj.t[window[int(np.argmax(ok))]]:.2f} s")
    return Outcome(desc, False, where)


def evaluate_all(items: list[Expectation], traj, final_hash: str) -> list[Outcome]:
    return [evaluate(e, traj, final_hash) for e in items]

