"""Continuous maps: pure functions from input values to joint targets (radians).

Three kinds, all written as data: linear (range, clamp, response curve), coupled
(one input drives several joints with signed gains, for symmetries like the
gymnast's "bound" and "trot" patterns) and pose grids (bilinear over named poses,
the paper's cat trot).
"""

from __future__ import annotations

import math
from operator import attrgetter

from puppet.data.interfaces import GridMapSpec
from puppet.interface.ik import hermite
from puppet.physics.kernel_maps import MAX_MIRRORS
from puppet.physics.servo import SET_TARGET


def shape(curve, u: float) -> float:
    """Apply a response curve to a normalised input u (0..1 inside the range)."""
    if curve == "linear":
        return u
    if curve == "smoothstep":
        return hermite(u)  # the same ease as an IK reach: 3u^2 - 2u^3, clamped
    p = curve.power  # sign-preserving power, so unclamped maps stay monotonic
    return math.copysign(abs(u) ** p, u)


def curve_function(curve):
    """``shape(curve, .)`` decided once, when a map is compiled: None for linear, else a
    function of u doing ``shape``'s arithmetic (a power curve is a model: comparing it
    with "linear" at every input would run the struct's ``__eq__``)."""
    if curve == "linear":
        return None
    if curve == "smoothstep":
        return hermite
    p = curve.power
    copysign = math.copysign
    return lambda u: copysign(abs(u) ** p, u)


def _grid_corners(rows: int, cols: int, mirror, x: float, y: float):
    """The four (row, col, weight) around (x, y) on a rows x cols grid."""
    if mirror:
        x = 1.0 - x if "x" in mirror else x
        y = 1.0 - y if "y" in mirror else y
    fx = min(1.0, max(0.0, x)) * (cols - 1)
    fy = (1.0 - min(1.0, max(0.0, y))) * (rows - 1)
    c0, r0 = min(int(fx), cols - 2) if cols > 1 else 0, min(int(fy), rows - 2) if rows > 1 else 0
    tx, ty = fx - c0, fy - r0
    c1, r1 = min(c0 + 1, cols - 1), min(r0 + 1, rows - 1)
    return ((r0, c0, (1 - tx) * (1 - ty)), (r0, c1, tx * (1 - ty)),
            (r1, c0, (1 - tx) * ty), (r1, c1, tx * ty))


CHANNEL = "channel."


def compile_map(spec, servos, pose_targets: dict[str, dict[str, float]], channels=None,
                frames=None, frame_owner=None):
    """A fast ``apply(values) -> joints written`` for one map (the mouse hot path):
    constants are worked out once and servos looked up once. ``channels``: the dict of
    channel values by bare name (``channel.NAME`` inputs are read there, not in
    ``values``: a stream's frame is stored with one dict update). ``frames``: the
    frame-target controller, for maps whose value is an angle in another frame, held
    under ``frame_owner`` (default: the frame owner, claimed; a feedback map's own)."""
    names = spec.inputs
    if not isinstance(spec, GridMapSpec) and spec.frame != "joint":
        return _compile_frame(spec, frames, channels, frame_owner)
    if channels is not None and any(n.startswith(CHANNEL) for n in names):
        if all(n.startswith(CHANNEL) for n in names):
            if isinstance(spec, GridMapSpec):
                bare = _renamed(spec, {n: n[len(CHANNEL):] for n in names})
                inner = compile_map(bare, servos, pose_targets)
                return lambda values: inner(channels)  # noqa: E731
            return _compile_linear(spec, servos, channels)
        inner = compile_map(spec, servos, pose_targets)  # channels and devices mixed

        def apply_mixed(values):
            merged = dict(values)
            merged.update((CHANNEL + k, v) for k, v in channels.items())
            return inner(merged)
        return apply_mixed
    if isinstance(spec, GridMapSpec):
        # Bilinear blend of the four grid poses around (x, y): row 0 is the top (y = 1),
        # column 0 the left (x = 0), inputs clamped to 0..1, axes in ``mirror`` flipped
        # first. Each cell's pose is reduced to (joint index, angle) for the joints
        # this map drives (``joints:``, else all of the pose's).
        x_name, y_name, mirror = spec.x, spec.y, spec.mirror
        rows, cols, only = len(spec.grid), len(spec.grid[0]), spec.joints
        joints: list[str] = []
        cells = []
        for row in spec.grid:
            cells.append([])
            for name in row:
                pairs = []
                for joint, angle in pose_targets[name].items():
                    if only is None or joint in only:
                        if joint not in joints:
                            joints.append(joint)
                        pairs.append((joints.index(joint), angle))
                cells[-1].append(tuple(pairs))
        targets = [servos[j] for j in joints]
        if all(sorted(i for i, _ in cell) == list(range(len(joints)))
               for row in cells for cell in row):  # every pose has every joint
            return _full_grid(x_name, y_name, rows, cols, mirror, targets, tuple(joints),
                              [[tuple(a for _, a in sorted(cell)) for cell in row]
                               for row in cells])

        def apply_grid(values):
            x, y = values.get(x_name), values.get(y_name)
            if x is None or y is None:
                return ()
            acc = [None] * len(joints)
            for r, c, w in _grid_corners(rows, cols, mirror, x, y):
                for i, angle in cells[r][c]:
                    a = acc[i]
                    acc[i] = (0.0 if a is None else a) + w * angle
            written = []
            for i, a in enumerate(acc):
                if a is not None:
                    targets[i].target = a
                    written.append(joints[i])
            return written
        return apply_grid
    return _compile_linear(spec, servos)


def _full_grid(x_name, y_name, rows, cols, mirror, servos, joints, cells):
    """``apply_grid`` when each grid pose gives every joint (``cells[r][c]``: the
    angles in ``joints`` order): each target is the same sum, corner by corner from
    0.0, without the accumulator's list and checks (a cat's legs: four grids a mouse
    event)."""
    flip_x, flip_y = bool(mirror) and "x" in mirror, bool(mirror) and "y" in mirror
    last_col, last_row = cols - 1, rows - 1

    def apply_full_grid(values):
        x, y = values.get(x_name), values.get(y_name)
        if x is None or y is None:
            return ()
        if flip_x:  # _grid_corners, inlined (max(0.0, v) is v if v > 0.0 else 0.0, and
            x = 1.0 - x  # min(1.0, m) is m if m < 1.0 else 1.0: the same values)
        if flip_y:
            y = 1.0 - y
        m = x if x > 0.0 else 0.0
        fx = (m if m < 1.0 else 1.0) * last_col
        m = y if y > 0.0 else 0.0
        fy = (1.0 - (m if m < 1.0 else 1.0)) * last_row
        c0 = min(int(fx), cols - 2) if cols > 1 else 0
        r0 = min(int(fy), rows - 2) if rows > 1 else 0
        tx, ty = fx - c0, fy - r0
        c1, r1 = min(c0 + 1, last_col), min(r0 + 1, last_row)
        w0, w1, w2, w3 = (1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty
        for servo, a0, a1, a2, a3 in zip(servos, cells[r0][c0], cells[r0][c1],
                                         cells[r1][c0], cells[r1][c1]):
            SET_TARGET(servo.spring._constraint,  # servo.target =
                       0.0 + w0 * a0 + w1 * a1 + w2 * a2 + w3 * a3)
        return joints
    apply_full_grid.grid = ((x_name, y_name, rows, cols), (flip_x, flip_y), servos, joints,
                            cells)
    return apply_full_grid


def _grid_run(grids):
    """Several ``apply_full_grid``'s on the same inputs and grid shape (a cat's four
    legs) as one applier: the corners and weights worked out once per mirror, then each
    target the same sum as its grid's own applier makes (the same bits). The grids drive
    different joints (else they are not folded), so the order of the writes is free:
    they go mirror by mirror. The corner cells' angles, per set of corners, are
    gathered once (cached)."""
    (x_name, y_name, rows, cols), _, _, _, _ = grids[0]
    flips = list(dict.fromkeys(g[1] for g in grids))  # the mirrors, in first-use order
    uses = [flips.index(g[1]) for g in grids]
    joints = tuple(j for g in grids for j in g[3])
    last_col, last_row = cols - 1, rows - 1
    gathered: dict = {}  # the corners of each mirror -> per mirror ((servo, a0..a3), ...)

    def gather(key):
        out = [[] for _ in flips]
        for (_, _, servos, _, cells), k in zip(grids, uses):
            r0, c0, r1, c1 = key[k]
            out[k] += zip(servos, cells[r0][c0], cells[r0][c1], cells[r1][c0], cells[r1][c1])
        gathered[key] = tuple(tuple(o) for o in out)
        return gathered[key]

    def apply_grid_run(values):
        x0, y0 = values.get(x_name), values.get(y_name)
        if x0 is None or y0 is None:
            return ()
        corners, weights = [], []
        for flip_x, flip_y in flips:  # apply_full_grid's arithmetic, per mirror
            x = 1.0 - x0 if flip_x else x0
            y = 1.0 - y0 if flip_y else y0
            m = x if x > 0.0 else 0.0
            fx = (m if m < 1.0 else 1.0) * last_col
            m = y if y > 0.0 else 0.0
            fy = (1.0 - (m if m < 1.0 else 1.0)) * last_row
            c0 = min(int(fx), cols - 2) if cols > 1 else 0
            r0 = min(int(fy), rows - 2) if rows > 1 else 0
            tx, ty = fx - c0, fy - r0
            corners.append((r0, c0, min(r0 + 1, last_row), min(c0 + 1, last_col)))
            weights.append(((1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty))
        key = tuple(corners)
        runs = gathered.get(key) or gather(key)
        for (w0, w1, w2, w3), run in zip(weights, runs):
            for servo, a0, a1, a2, a3 in run:  # (a re-seat may give a servo a new spring)
                SET_TARGET(servo.spring._constraint,
                           0.0 + w0 * a0 + w1 * a1 + w2 * a2 + w3 * a3)
        return joints
    compiled = _grid_run_kernel(grids, flips, uses, x_name, y_name, joints)
    return apply_grid_run if compiled is None else compiled


def _grid_run_kernel(grids, flips, uses, x_name, y_name, joints):
    """``apply_grid_run`` as one call of the kernel's ``pk_grid_run`` (the same
    arithmetic, the same bits: ``physics.kernel_maps``); None without the kernel."""
    from puppet.physics import kernel

    kern = kernel.get()
    if kern is None or len(flips) > MAX_MIRRORS:
        return None
    ffi, run = kern.ffi, kern.lib.pk_grid_run
    (_, _, rows, cols), _, _, _, _ = grids[0]
    servos = [servo for g in grids for servo in g[2]]
    mirror = [k for g, k in zip(grids, uses) for _ in g[2]]
    cells = [g[4][r][c][q] for g in grids for q in range(len(g[2]))
             for r in range(rows) for c in range(cols)]
    g = ffi.new("pk_grid_table *")
    keep = [ffi.new("int[]", mirror), ffi.new("double[]", cells),
            ffi.new("void *[]", len(servos))]
    g.use, g.cells, g.spring = keep
    g.n_flips, g.rows, g.cols, g.n = len(flips), rows, cols, len(servos)
    for k, (flip_x, flip_y) in enumerate(flips):
        g.flip_x[k], g.flip_y[k] = int(flip_x), int(flip_y)
    spring_of = attrgetter("spring")
    bound = [None]  # the springs the kernel points at (a restore binds new ones)

    def bind():
        springs = tuple(map(spring_of, servos))
        if springs != bound[0]:
            for j, spring in enumerate(springs):
                keep[2][j] = kern.pointer(spring._constraint)
            bound[0] = springs

    def apply_grid_run_kernel(values):
        x0, y0 = values.get(x_name), values.get(y_name)
        if x0 is None or y0 is None:
            return ()
        bind()
        run(g, x0, y0)
        return joints
    apply_grid_run_kernel.keep = (g, keep)  # (the arrays live as long as the applier)
    # the table, bound to the springs of now (bind), for the kernel's event runs
    apply_grid_run_kernel.grid_run = (g, bind, x_name, y_name, joints)
    return apply_grid_run_kernel


def _compile_linear(spec, servos, channels=None):
    """A linear map's applier (``channels``: where ``channel.NAME`` inputs are read)."""
    outs = [(servos[j], g) for j, g in spec.gains().items()]
    joints = tuple(spec.gains())
    if spec.clamp and len(outs) == 1:
        return _compile_clamped_linear(spec, outs[0], joints, channels)
    value = _unit(spec, channels)

    def apply_linear(values):
        v = value(values)
        if v is None:
            return ()
        for servo, gain in outs:  # servo.target = (a re-seat may give it a new spring)
            SET_TARGET(servo.spring._constraint, gain * v)
        return joints
    x0, inv, lo, span, clamp, f, name, source = _unit_numbers(spec, channels)
    if clamp and f is None:  # clamped, no curve: one plain row a joint for the kernel's
        # event runs (gain * (lo + u * span): the same operations as ``value``'s, then
        # ``gain * v``; what ``_plain_run`` reads)
        apply_linear.plain_run = (source, tuple(
            (name, x0, inv, lo, span, gain, servo, joint)
            for (servo, gain), joint in zip(outs, joints)))
    return apply_linear


def _compile_clamped_linear(spec, out, joints, channels=None):
    """The commonest map (one joint, clamped: nearly every mouse and channel map of the
    shipped files) in one function: ``_unit``'s arithmetic, operation for operation (the
    same bits), without its call; it runs for each map at every mouse move or stream
    frame."""
    (x0, x1), (y0, y1) = spec.from_, spec.to
    inv, lo, span = 1.0 / (x1 - x0), math.radians(y0), math.radians(y1 - y0)
    servo, gain = out
    name = spec.input
    f = curve_function(spec.curve)
    if f is not None:
        value = _unit(spec, channels)

        def apply_curved(values):
            v = value(values)
            if v is None:
                return ()
            SET_TARGET(servo.spring._constraint, gain * v)  # servo.target =
            return joints
        return apply_curved
    source = None  # where the input is read: the values handed in, or the channels
    if name.startswith(CHANNEL) and channels is not None:
        name, source = name[len(CHANNEL):], channels  # by bare name

    def apply_input(values):
        v = (values if source is None else source).get(name)
        if v is None:
            return ()
        u = (v - x0) * inv
        u = 0.0 if u < 0.0 else 1.0 if u > 1.0 else u
        SET_TARGET(servo.spring._constraint, gain * (lo + u * span))  # servo.target =
        return joints
    apply_input.plain = (source, (name, x0, inv, lo, span, gain, servo, joints[0]))
    return apply_input


def fused(appliers) -> list:
    """``appliers`` with each run of two or more plain maps (``apply_input``'s: one joint,
    clamped, linear) that read one source folded into one applier, in the same order
    with the same arithmetic (the same bits). A 120 Hz stream of many channels runs
    its maps once a frame; one loop instead of a call per map is most of what is left
    to win on that path (bench: the channels stream overhead)."""
    out, run = [], []

    def close():
        if len(run) > 1:
            out.append(_plain_run(run[0].plain[0], [a.plain[1] for a in run]))
        else:
            out.extend(run)
        run.clear()

    grids = []  # likewise a run of full grids on the same inputs and grid shape

    def close_grids():
        joints = [j for a in grids for j in a.grid[3]]
        if len(grids) > 1 and len(set(joints)) == len(joints):  # (each joint once)
            out.append(_grid_run([a.grid for a in grids]))
        else:
            out.extend(grids)
        grids.clear()

    for applier in appliers:
        grid = getattr(applier, "grid", None)
        if grids and (grid is None or grid[0] != grids[0].grid[0]):
            close_grids()
        if grid is not None:
            close()
            grids.append(applier)
            continue
        plain = getattr(applier, "plain", None)
        if plain is None or (run and run[0].plain[0] is not plain[0]):
            close()
        if plain is None:
            out.append(applier)
        else:
            run.append(applier)
    close()
    if grids:
        close_grids()
    return out


def _plain_run(source, params):
    params = tuple(params)
    set_target = SET_TARGET
    every = tuple(p[7] for p in params)  # the joints written when every input has a value

    def apply_plain_run(values):
        get = (values if source is None else source).get
        missing = False
        for name, x0, inv, lo, span, gain, servo, _ in params:
            v = get(name)
            if v is None:
                missing = True
                continue
            u = (v - x0) * inv
            u = 0.0 if u < 0.0 else 1.0 if u > 1.0 else u
            set_target(servo.spring._constraint, gain * (lo + u * span))  # servo.target =
        if missing:  # the joints of the inputs that have one
            return [p[7] for p in params if get(p[0]) is not None]
        return every
    apply_plain_run.plain_run = (source, params)  # (what the kernel's event runs read)
    return apply_plain_run


def _unit_numbers(spec, channels=None):
    """What a map's value is worked out from: x0, 1 / (x1 - x0), lo and span (radians),
    clamp, the curve (None: linear), the input's name and where it is read (None: the
    values handed in; a ``channel.NAME`` input from ``channels`` by its bare name)."""
    (x0, x1), (y0, y1) = spec.from_, spec.to
    inv, lo, span = 1.0 / (x1 - x0), math.radians(y0), math.radians(y1 - y0)
    clamp, f, name = spec.clamp, curve_function(spec.curve), spec.input
    source = None
    if name.startswith(CHANNEL) and channels is not None:
        name, source = name[len(CHANNEL):], channels  # by bare name
    return x0, inv, lo, span, clamp, f, name, source


def _unit(spec, channels=None):
    """``value(values) -> the map's output in radians`` (None without its input); a
    ``channel.NAME`` input is read from ``channels`` by its bare name when given."""
    x0, inv, lo, span, clamp, f, name, source = _unit_numbers(spec, channels)

    def value(values):
        v = (values if source is None else source).get(name)
        if v is None:
            return None
        u = (v - x0) * inv
        if clamp:
            u = 0.0 if u < 0.0 else 1.0 if u > 1.0 else u
        return lo + (u if f is None else f(u)) * span
    return value


def compile_contribution(spec, channels=None):
    """An 'add' map: ``contribution(values) -> [(joint, radians)]`` to add to targets (a
    constant ``add:`` map: the same offset at every control step). Its ``row``, when it
    has one, is what the compiled feedback reads instead (``controllers.feedback_kernel``:
    constant?, input, x0, 1 / (x1 - x0), lo, span, clamp, [(joint, gain or value)])."""
    gains = list(spec.gains().items())
    if getattr(spec, "add", None) is not None:
        constant = [(j, g * math.radians(spec.add)) for j, g in gains]

        def contribution_constant(values):
            return constant
        contribution_constant.row = (True, None, 0.0, 0.0, 0.0, 0.0, False, constant)
        return contribution_constant
    # (the numbers feedback's compiled call reads instead: controllers.feedback_kernel.Plan;
    # a curve or a channel input leaves it to this Python)
    x0, inv, lo, span, clamp, f, name, source = _unit_numbers(spec, channels)
    value = _unit(spec, channels)

    def contribution(values):
        v = value(values)
        if v is None:
            return ()
        return [(j, g * v) for j, g in gains]
    if f is None and source is None:
        contribution.row = (False, name, x0, inv, lo, span, clamp, gains)
    return contribution


def _compile_frame(spec, frames, channels, owner=None):
    """A map whose value is a link's angle in the world (``frame: world``) or relative
    to a link: it holds frame targets (re-solved at the control rate), claiming them."""
    from puppet.interface.poses import made_frame_target

    value = _unit(spec, channels)
    ref = None if spec.frame == "world" else spec.frame
    parent = spec.hold == "parent"
    gains = list(spec.gains().items())
    holder = getattr(frames, "holder", None)
    if holder is not None:  # FrameTargets.hold, each joint's lookups done once
        holds = [(g, holder(joint, ref, parent, owner)) for joint, g in gains]
        (x0, x1), (y0, y1) = spec.from_, spec.to
        inv, lo, span = 1.0 / (x1 - x0), math.radians(y0), math.radians(y1 - y0)
        name, clamp = spec.input, spec.clamp
        if curve_function(spec.curve) is not None or name.startswith(CHANNEL):
            return _held_frame(value, holds)

        def apply_frame_held(values):  # _unit's value, inlined (the same arithmetic)
            v = values.get(name)
            if v is not None:
                u = (v - x0) * inv
                if clamp:
                    u = 0.0 if u < 0.0 else 1.0 if u > 1.0 else u
                v = lo + u * span
                for g, hold_at in holds:
                    hold_at(g * v)
            return ()  # held under the frame owner: nothing for the caller to take
        if clamp:  # (what the kernel's event runs read: session.event_runs)
            apply_frame_held.frame_run = (name, x0, inv, lo, span, frames, tuple(
                (g, joint, ref, parent, owner) for joint, g in gains))
        return apply_frame_held

    def apply_frame(values):
        v = value(values)
        if v is not None:
            for joint, g in gains:
                frames.hold(joint, made_frame_target(ref, g * v, parent), owner)
        return ()  # held under the frame owner: nothing for the caller to take
    return apply_frame


def _held_frame(value, holds):
    """A frame map's applier through its ``_unit`` (a curve, a channel input)."""
    def apply_frame_held(values):
        v = value(values)
        if v is not None:
            for g, hold_at in holds:
                hold_at(g * v)
        return ()  # held under the frame owner: nothing for the caller to take
    return apply_frame_held


def _renamed(spec, names: dict[str, str]):
    """A grid map reading its inputs under other names."""
    return spec.model_copy(update={"x": names[spec.x], "y": names[spec.y]})
