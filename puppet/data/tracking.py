"""An interface's ``tracking:`` section: how a performance (mocap channels) drives the
figure, and the gain presets of KD control (Nguyen et al. 2010).

Two ways to follow a performer, selected by the ``track`` action (a key, a state's
``enter``, or ``start``):

- ``angles``: joint tracking - each tracked joint's target is its channel's angle;
- ``kd``: KD control - the same joint targets, with inertia-scaled gains (stiffness
  ``kq * I``, damping ``dq * I``, I the inertia of everything beyond the joint), plus
  Cartesian PD pulls of each link toward where the performed pose puts it (``kp``,
  ``dp``; ``scale`` multiplies a link's, the paper's feet 125x, shins 25x, thighs 5x
  keep the figure up and walking where the performer walks). ``kinematic: off`` drops the pulls
  (free fall) and keeps the joint tracking.

A sample older than ``lost_after`` seconds is tracking lost: the tracker stands the
figure in the ``stand`` pose (or, without one, lets go of its joints: what the keys and
maps say holds them; ``lost``, an action, runs then) until samples come again, when it
takes them back over ``blend`` seconds (``found`` runs then). A push judged a fall is
followed by ``reaction.get_up``: the recovery poses, then the performer again.
"""

from __future__ import annotations

from typing import Annotated, Literal

from puppet.data.actions import ActionSpec
from puppet.data.ranges import AngleChange, Num
from puppet.data.validate import Meta, Spec, field

Gain = Num("gain")


class GainsSpec(Spec, kw_only=True):
    """KD gains: Cartesian kp (N/m), dp (N*s/m); joint kq (1/s^2), dq (1/s), both
    multiplied by the inertia beyond the joint."""

    kp: Gain = 160.0
    dp: Gain = 25.0
    kq: Gain = 450.0
    dq: Gain = 10.0


# The paper's table (Nguyen et al. 2010, section 6): kp, dp, kq, dq.
PRESETS: dict[str, GainsSpec] = {
    "default": GainsSpec(kp=160.0, dp=25.0, kq=450.0, dq=10.0),
    "balloon": GainsSpec(kp=0.0, dp=0.0, kq=200.0, dq=2.0),  # in the air
    "stapler": GainsSpec(kp=200.0, dp=25.0, kq=450.0, dq=10.0),
    "giant": GainsSpec(kp=420.0, dp=50.0, kq=1200.0, dq=15.0),
    "glider": GainsSpec(kp=1000.0, dp=125.0, kq=450.0, dq=10.0),
}


class ReactionCaseSpec(Spec, kw_only=True):
    """How far the pulls give way after a push, and for how long: to ``weight`` at
    once, held ``hold`` s, then back to full over ``recover`` s."""

    weight: Num("fraction") = 0.3
    hold: Num("duration") = 0.2
    recover: Num("positive_duration") = 0.6


class GetUpStepSpec(Spec, kw_only=True):
    """One pose of a get-up: the interface's pose ``pose`` (joint angles), the root link
    at ``angle`` degrees in the world (the pelvis level on hands and knees: -90),
    reached from the last over ``hold`` s."""

    pose: str
    angle: AngleChange = 0.0
    hold: Num("positive_duration") = 1.0


class GetUpSpec(Spec, kw_only=True):
    """A get-up after a fall (Oshita 2006's stand-up, through Laszlo et al.'s recovery
    poses): KD control of ``steps`` in turn, where the figure lies (its lowest point on
    the ground), each blended in from the last, then back to the performer over the
    tracking's ``blend``. No levitation: while no foot (``tracking.feet``) nor one of
    ``hands`` touches the ground, no pull lifts a link (the body rises only by pushing
    on the ground), and none lifts one faster than ``rise``."""

    hands: list[str] = field(default_factory=list)  # links that push as the feet do
    rise: Num("speed") = 0.5  # m/s: the pulls lift no link faster than this
    steps: Annotated[list[GetUpStepSpec], Meta(min_length=1)]


class SearchWeightsSpec(Spec, kw_only=True):
    """How much each feature counts in a library search's distance (squared
    differences): the trunk's angle (per rad) and turning rate (per rad/s) high, as
    Zordan et al. weigh the root's orientation and angular velocity; the centre of
    mass's velocity (per m/s); each joint's angle (per rad)."""

    trunk: Gain = 10.0
    spin: Gain = 2.0
    com: Gain = 1.0
    joints: Gain = 0.3


class LibrarySpec(Spec, kw_only=True):
    """A motion-library reaction (Zordan et al. 2005): ``after`` s into a reaction of
    one of ``cases`` the tracker searches the library ``file`` (assets/mocap/NAME.json,
    written by ``puppet mocap library FOLDER``) for the window whose first frame best
    matches the figure's state (``weights``), follows it - blended in from the
    performer over ``blend`` s, placed where the figure is - to its end, then blends
    back to the performer over the tracking's ``blend``. The search reads only the
    figure's state and the file: a replay finds the same window."""

    file: str
    cases: list[Literal["small", "large", "fall"]] = field(default_factory=lambda: ["large"])
    after: Num("duration") = 0.1  # s after the push is judged: the state searched with
    blend: Num("duration") = 0.2  # s: from the performer into the window
    # how much of the pulls acts on the window (from the case's weight, over 'blend')
    weight: Num("fraction") = 1.0
    weights: SearchWeightsSpec = field(default_factory=SearchWeightsSpec)


class ReactionSpec(Spec, kw_only=True):
    """Impact reactions (Oshita 2006): after a push or a drag, KD control's pulls give
    way so the figure reacts, then come back. The case is judged at the next control
    step by the extrapolated centre of mass against the support (the feet on the
    ground, widened to where the performance's own would be): inside it or within
    ``small_margin`` m of it, ``small`` (a dip, then recover); beyond it by up to
    ``step_margin`` m, ``large`` (longer and weaker, and one foot of ``feet`` makes a
    protective step: lifted and put down ``step_past`` beyond the extrapolated centre
    of mass, then back to the performance as the pulls come back); further, ``fall``
    (the pulls let go, the figure falls, then they bring it back up: the get-up)."""

    small_margin: Num("corner") = 0.05  # m beyond the support: still small
    step_margin: Num("size") = 0.3  # m beyond the support: large, not a fall
    # s a large push's protective step takes (a foot of 'feet' lifted and put down past the
    # extrapolated centre of mass)
    step_time: Num("positive_duration") = 0.35
    step_lift: Num("corner") = 0.1  # m the stepping foot is lifted
    step_past: Num("corner") = 0.1  # m past the extrapolated centre of mass the foot lands
    small: ReactionCaseSpec = field(
        default_factory=lambda: ReactionCaseSpec(weight=0.3, hold=0.15, recover=0.5))
    large: ReactionCaseSpec = field(
        default_factory=lambda: ReactionCaseSpec(weight=0.1, hold=0.5, recover=1.0))
    fall: ReactionCaseSpec = field(
        default_factory=lambda: ReactionCaseSpec(weight=0.0, hold=1.5, recover=2.0))
    # after a fall (and fall.hold), the figure gets up through these poses, then follows the
    # performer again (Oshita's stand-up); absent, the pulls come back over fall.recover
    get_up: GetUpSpec | None = None
    # a reaction of library.cases follows a window of a motion library found by a search
    # (Zordan 2005) instead of the performer (and takes no protective step)
    library: LibrarySpec | None = None


class WalkInPlaceSpec(Spec, kw_only=True):
    """Walking in place (Oshita 2006): a performer stepping on the spot - the feet
    lifted by turns, read from the performed pose (one of ``tracking.feet`` ``lift`` m
    above the other) - makes the figure walk forward at the rhythm's speed. The walk
    is an example gait cycle (``cycle``: from, until, s of the clip ``clip`` of the
    motion library ``library``), played at the performer's step rate and phase-locked
    to their lifts; its ``joints`` (channels: the legs, the pelvis) replace the
    performer's, blended in over ``blend`` s, the rest (arms, trunk, head) stay the
    performer's; ``root.x`` goes on by the cycle's travel. Step periods outside
    ``steps`` (s) are not a rhythm; no step for ``stop_after`` s stops the walk (blended
    out: the figure stands where it got to, following the performer again)."""

    library: str  # a motion library (assets/mocap/NAME.json)
    clip: str  # the name of its clip that holds the example walk
    cycle: tuple[Num("time"), Num("time")]  # s: one gait cycle of it (two steps)
    joints: list[str]  # channels taken from the walk
    lift: Num("corner") = 0.05
    steps: tuple[Num("positive_duration"), Num("positive_duration")] = (0.25, 1.2)
    stop_after: Num("positive_duration") = 1.2
    blend: Num("duration") = 0.4


class ContactsSpec(Spec, kw_only=True):
    """Intentional contacts (Ishigaki et al. 2009): while a grasp chain of ``hands``
    holds (the hand held to a bar by the grasp's pin joint), the figure's centre of
    mass is driven about it by a damped linear spring and a swing PD: the relative
    vector r (the hand less the centre of mass) follows the performer's (the effector
    channels ``NAME.x``, ``NAME.y``: m from their centre of mass) - its angle's change
    since the grasp (``swing``, N*m/rad) and its turning rate (``swing_damping``,
    N*m*s/rad: Ishigaki's monkey bars track the user's angular velocity only), its
    length's change (``spring``, N/m; ``damping``, N*s/m). The forces act on the centre
    of mass alone (every link the same acceleration: no turn)."""

    hands: dict[str, str]  # grasp chain -> the performer's effector channel (NAME.x/.y)
    swing: Num("gain") = 0.0
    swing_damping: Num("gain") = 150.0
    spring: Num("gain") = 0.0
    damping: Num("gain") = 0.0


class RootChannelsSpec(Spec, kw_only=True):
    """The channels that place the performed pose in the world, and the joint whose
    hinge is the root point (the mapping's ``root.point``)."""

    x: str = "root.x"  # channel: m travelled forward
    y: str = "root.y"  # channel: m above the ground
    angle: str = "root.angle"  # channel: the root link's angle, deg
    # channel: m the performer's feet are off the floor (0: one is down)
    clearance: str = "clearance"
    at: str  # a joint on the root link whose hinge the root channels place (the hips: hip_near)


class TrackingSpec(Spec, kw_only=True):
    # the mocap mapping the channels come from (assets/mappings/NAME.yaml)
    mapping: str | None = None
    # the joints that follow the channel of their name ('all': every actuated joint with a channel)
    joints: list[str] | Literal["all"] = "all"
    # joint -> channel, where the names differ
    channels: dict[str, str] = field(default_factory=dict)
    root: RootChannelsSpec | None = None  # for kd: where the performed pose stands
    gains: Literal["default", "balloon", "stapler", "giant", "glider"] | GainsSpec = "default"
    # link -> Cartesian gain multiplier (Nguyen: feet 125, shins 25, thighs 5; others 1)
    scale: dict[str, Num("ratio")] = field(default_factory=dict)
    # links the performed pose stands on: it is moved up or down until the lowest of them touches
    # the ground (the performer's other proportions, a floor offset)
    feet: list[str] = field(default_factory=list)
    # impact reactions of KD control (null: none, the pulls hold through a push)
    reaction: ReactionSpec | None = field(default_factory=ReactionSpec)
    start: Literal["off", "angles", "kd"] = "off"  # tracking at the start
    lost_after: Num("positive_duration") = 0.25  # s without a sample: tracking lost
    # a pose of the interface (joint angles) the tracker stands the figure in while the stream
    # is lost: KD control of that pose where the figure is (the root over the middle of its feet,
    # the pelvis upright), blended in from the last frame over 'blend' s, and back to the
    # performer over as long when the stream returns; absent, tracking lets go of the joints
    stand: str | None = None
    # what the figure does when tracking is lost (its balance: a pose, a state of the interface);
    # the keys drive it too
    lost: ActionSpec | None = None
    # what is done when the stream comes back and tracking takes the joints again (leave the
    # balance state)
    found: ActionSpec | None = None
    # s over which tracking takes the joints back - from their targets then to the performer's,
    # the pulls from none to full - when the stream comes back, or a 'track' action starts it
    # (not at the interface's start)
    blend: Num("duration") = 0.0
    # stepping on the spot walks the figure forward (Oshita 2006; null: the performer's
    # steps are followed as they are)
    walk_in_place: WalkInPlaceSpec | None = None
    # a held hand moves the centre of mass as the performer's hand moves about theirs
    # (Ishigaki 2009; null: none)
    contacts: ContactsSpec | None = None

    @property
    def preset(self) -> GainsSpec:
        return PRESETS[self.gains] if isinstance(self.gains, str) else self.gains


def mapping_problem(tracking: TrackingSpec, mapping, actuated: list[str]) -> str | None:
    """What in ``tracking`` the channels of ``mapping`` (a MappingSpec) cannot give, or
    None: a tracked joint with no channel would never move, KD control with no root
    channels would never pull."""
    made = set(mapping.channel_names())
    joints = actuated if tracking.joints == "all" else tracking.joints
    wanted = [tracking.channels.get(j, j) for j in joints]
    if not any(c in made for c in wanted):
        return (f"mapping '{mapping.name}' makes none of the tracked joints' channels "
                f"({', '.join(wanted)}); expected channels named like the joints, or "
                f"'channels: {{joint: channel}}'")
    if tracking.joints != "all":
        missing = [c for c in wanted if c not in made]
        if missing:
            return (f"mapping '{mapping.name}' makes no channel {', '.join(missing)} for "
                    f"the tracked joints; it makes {', '.join(sorted(made))}")
    root = tracking.root
    if root is not None:
        missing = [c for c in (root.x, root.y, root.angle) if c not in made]
        if missing:
            return (f"mapping '{mapping.name}' makes no {', '.join(missing)}, which "
                    f"tracking.root reads to place the performed pose")
    return None


def interface_mapping_problem(interface, character, mapping) -> str | None:
    """``mapping_problem`` for an interface (its ``tracking``) on a character (its
    actuated joints), the one check ``puppet play --mocap``, ``puppet tune``'s ``mocap``
    and ``puppet check`` make; None when the interface tracks nothing."""
    if interface.tracking is None:
        return None
    return mapping_problem(interface.tracking, mapping, [j.name for j in character.actuated])
