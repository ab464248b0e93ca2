"""Heads-up display: time, slowdown (requested and measured), fps, scene, bindings."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import pygame

from puppet.app.describe import app_lines, control_rows, where_line
from puppet.app.keymap import draw_keymap
from puppet.app.render import text as text_surface
from puppet.session import Session

TEXT = (40, 44, 52)
DIM = (110, 116, 128)
PANEL = (255, 255, 255, 200)


MESSAGE_SECONDS = 5.0  # how long a session message stays on screen


@dataclass
class HudInfo:
    slowdown: float = 1.0
    measured: float | None = None
    fps: float | None = None
    paused: bool = False
    show_help: bool = False
    message: str = ""
    message_error: bool = False  # drawn in red; other messages are news, not errors
    scrubbing: bool = False  # the rewind key is held
    replaying: str = ""  # the log a window replay plays (its events, not the devices)
    overlay: bool = False  # the centre-of-mass overlay is on (see render.draw_balance)
    branch: int | None = None  # the branch selected (history.branches index), listed
    # pixels from the window's top to below the compact top panels (the last drawn): a
    # scene's fixed view is framed under them (camera.reserve_top)
    top_band: int | None = None
    sources: list = field(default_factory=list)  # status lines of the input sources
    playtest: str = ""  # the last playtest figure of this interface (puppet playtest)
    _seen_serial: int = 0
    _message_until: float = 0.0
    # What the HUD drew last, kept by what it depends on (see draw_hud and draw_rows), so
    # that a frame that changes nothing measures no text again
    _rows: tuple = field(default=(None, None), repr=False, compare=False)
    _laid: dict = field(default_factory=dict, repr=False, compare=False)
    _keymap: dict = field(default_factory=dict, repr=False, compare=False)  # F1's pictures

    def follow_messages(self, session: Session, now: float) -> None:
        """Show the session's newest message (e.g. a recovered blow-up) for
        MESSAGE_SECONDS of the caller's clock (wall time in the window, video time in
        an export), then clear it."""
        if session.message_serial != self._seen_serial:
            self._seen_serial, self._message_until = session.message_serial, now + MESSAGE_SECONDS
            self.message = session.message
            self.message_error = session.message_error
        elif self.message and now > self._message_until:
            self.message = ""


TITLE = (20, 60, 120)
ERROR = (160, 30, 30)
NEWS = (30, 70, 130)
ROW = 18  # pixels per row of the small font
GAP = 14  # pixels between a row's key and its text


COMPACT_SHARE = 0.4  # of the window's width: the compact key panel at most (long texts
# wrapped onto the next rows), so that the gap between the two top panels, where the
# camera puts the character (camera.LEAD_X), stays free


_PANELS: dict[tuple[int, int], pygame.Surface] = {}  # size -> a filled panel (kept)
PANELS_KEPT = 32  # sizes kept: the HUD draws a handful a frame, a few sizes each


def _panel(surface, rect) -> None:
    """The translucent panel under a block of text: one surface per size, filled
    once (making and filling a new one each frame cost more than blitting it)."""
    size = (rect.width, rect.height)
    panel = _PANELS.get(size)
    if panel is None:
        if len(_PANELS) >= PANELS_KEPT:
            del _PANELS[next(iter(_PANELS))]  # the oldest
        panel = _PANELS[size] = pygame.Surface(size, pygame.SRCALPHA)
        panel.fill(PANEL)
    surface.blit(panel, rect.topleft)


def _fmt_rate(x: float | None) -> str:
    if x is None:
        return "-"
    return f"{x:.2f}x" if x < 1 else f"{x:.1f}x" if x < 10 else f"{x:.0f}x"


def fit(font: pygame.font.Font, text: str, width: int) -> str:
    """``text`` cut (with an ellipsis) to ``width`` pixels as ``font`` draws it."""
    if font.size(text)[0] <= width:
        return text
    while text and font.size(text + "...")[0] > width:
        text = text[:-1]
    return text.rstrip() + "..."


def wrap(font: pygame.font.Font, text: str, width: int) -> list[str]:
    """``text`` broken at spaces into lines of at most ``width`` pixels as ``font``
    draws them (a single word wider than that is cut with an ellipsis)."""
    lines: list[str] = []
    line = ""
    words: list[str] = []
    for word in text.split(" "):  # ".." and "..." stay with the word after them
        if words and words[-1] in ("..", "..."):
            words[-1] += " " + word
        else:
            words.append(word)
    for word in words:
        trial = f"{line} {word}" if line else word
        if line and font.size(trial)[0] > width:
            lines.append(line)
            trial = word
        line = trial
    lines.append(line)
    return [fit(font, t, width) for t in lines]


def wrap_rows(font: pygame.font.Font, rows: list[tuple[str, str]],
              max_width: int) -> list[tuple[str, str]]:
    """(key, text) rows with each text too long for a panel ``max_width`` wide broken
    onto rows of its own under it (their key ""), so that no text is cut."""
    keyed = [(k, t) for k, t in rows if t]
    key_w = max((font.size(k)[0] for k, _ in keyed), default=0) + GAP
    room = max(60, max_width - 16 - key_w - font.size("  ")[0])
    out: list[tuple[str, str]] = []
    for k, t in rows:
        if not t:  # a heading: across the panel, wrapped too (a state per machine)
            out += [(line, "") for line in wrap(font, k, max(60, max_width - 16))] if k \
                else [(k, t)]
            continue
        first, *rest = wrap(font, t, room)
        out.append((k, first))
        out += [("", "  " + more) for more in rest]
    return out


def layout_rows(font: pygame.font.Font, rows: list[tuple[str, str]],
                max_width: int) -> tuple[int, int, list[tuple[str, str]]]:
    """Lay out (key, text) rows by measured width: (key column width, panel width,
    rows with each text fitted). A row with no text is a heading across both columns."""
    keyed = [(k, t) for k, t in rows if t]
    key_w = max((font.size(k)[0] for k, _ in keyed), default=0) + GAP
    text_w = max((font.size(t)[0] for _, t in keyed), default=0)
    head_w = max((font.size(k)[0] for k, t in rows if not t), default=0)
    width = min(max(key_w + text_w, head_w) + 16, max_width)
    room = max(20, width - 16 - key_w)
    return key_w, width, [(fit(font, k, width - 16), "") if not t else (k, fit(font, t, room))
                          for k, t in rows]


MIN_COLUMN = 300  # pixels: a column of a panel at least (more, if the panel itself is)
BAR_HEIGHT = 30  # the timeline bar along the bottom, with its margin


def _columns(small, rows: list[tuple[str, str]], per: int,
             share: int) -> list[list[tuple[str, str]]]:
    """``rows`` in columns of at most ``per`` rows ``share`` pixels wide, each wrapped
    by its own key column's width; a row's wrapped lines stay in one column."""
    columns, rest = [], list(rows)
    while rest:
        n = min(per, len(rest))
        wrapped = wrap_rows(small, rest[:n], share)
        while len(wrapped) > per and n > 1:
            n -= 1
            wrapped = wrap_rows(small, rest[:n], share)
        columns.append(wrapped[:per])
        rest = rest[n:]
    return columns


LAID_KEPT = 8  # panels laid out kept (draw_rows' cache): the controls and the legend,
# and a few more while the window is resized


def _lay_out(small, rows: tuple[tuple[str, str], ...], per: int,
             max_width: int) -> tuple[int, int, list[tuple[pygame.Surface, int, int]]]:
    """(width, height, [(text drawn, x, y) relative to the panel]) of a panel of ``rows``
    as ``draw_rows`` lays them out: a function of its arguments alone."""
    share, count = max_width, 0
    while True:  # wrap for the columns' width; more rows may need one more column
        columns = _columns(small, rows, per, share)
        if len(columns) <= count or count > 8:
            break
        count = len(columns)
        share = max(max_width // count, min(max_width, MIN_COLUMN))  # too narrow to read:
        # wider than asked (the panel reaches further left)
    laid = [layout_rows(small, col, share) for col in columns]
    width = sum(w for _, w, _ in laid)
    height = 8 + max(len(col) for col in columns) * ROW
    blits = []
    x = 0
    for key_w, col_w, col in laid:
        for i, (k, text) in enumerate(col):
            y = 4 + i * ROW
            if not text:
                blits.append((small.render(k, True, TITLE), x + 8, y))
                continue
            blits.append((small.render(k, True, TEXT), x + 8, y))
            blits.append((small.render(text, True, DIM), x + 8 + key_w, y))
        x += col_w
    return width, height, blits


def draw_rows(surface, small, rows: list[tuple[str, str]], right: int | None, top: int,
              bottom: int, max_width: int, cache: dict | None = None) -> pygame.Rect:
    """A panel of (key, text) rows laid out by measured width, its right edge at
    ``right`` (None: its left edge at 8). Rows that do not fit above ``bottom`` go on in
    a second column (and so on), each laid out by its own width. ``cache``: a dict that
    keeps the last few layouts (and their rendered text) by all they depend on - the
    font, the rows, the rows a column holds, the width allowed - across frames."""
    per = max(1, (bottom - top - 8) // ROW)
    key = (small, tuple(rows), per, max_width)
    laid = cache.get(key) if cache is not None else None
    if laid is None:
        laid = _lay_out(small, key[1], per, max_width)
        if cache is not None:
            if len(cache) >= LAID_KEPT:
                del cache[next(iter(cache))]  # the oldest
            cache[key] = laid
    width, height, blits = laid
    x0 = 8 if right is None else right - width
    rect = pygame.Rect(x0, top, width, height)
    _panel(surface, rect)
    for text, dx, dy in blits:
        surface.blit(text, (x0 + dx, top + dy))
    return rect


def legend_rows(session: Session) -> list[tuple[str, str]]:
    """What the marks on screen mean (the help panel's last part)."""
    keys = session.app_keys
    return [("on screen", ""),
            ("orange +", "the centre of mass"),
            ("bar: blue", f"the span you can rewind (hold {keys['rewind']})"),
            ("bar: orange", f"your checkpoints ({keys['checkpoint']}); grey: automatic ones"),
            ("bar: dark", "now; the bar's ends are 0 s and the latest time"),
            ("N m", "distance along the ground, in metres")]


def world_changes(session: Session) -> str:
    """What the interface's keys changed in the world, against the scene ("" if
    nothing): gravity, the ground's friction, random kicks switched on."""
    scene, sim = session.setup.scene, session.sim
    parts = []
    gravity = tuple(sim.space.gravity)
    if gravity != tuple(scene.gravity):
        parts.append(f"gravity {gravity[0]:g}, {gravity[1]:g} m/s2 "
                     f"(scene {scene.gravity[0]:g}, {scene.gravity[1]:g})")
    planned = [g.friction for g in scene.ground for _ in zip(g.points, g.points[1:])]
    now = [seg.friction for seg in sim.ground]
    if now != planned:
        parts.append(f"friction {now[0]:g}" if len(set(now)) == 1 else "friction changed")
    if session.runtime.perturber.on and not session.setup.interface.perturbation.start_on:
        parts.append("random kicks on")
    return "world: " + ", ".join(parts) if parts else ""


def _control_panel(session: Session, info: HudInfo,
                   show_help: bool | None = None) -> tuple[tuple[str, str], ...]:
    """The controls panel's rows: a function of the interface (a hot reload brings a
    new one), its live state and mode, each state machine's state and the help key's
    toggle (``show_help``: the rows for that toggle, default the HUD's), kept in
    ``info`` while those stay the same."""
    spec, runtime = session.setup.interface, session.runtime
    states = runtime.states
    show_help = info.show_help if show_help is None else show_help
    key = (spec, runtime.state, runtime.mode, tuple(states.items()) if states else (),
           show_help)  # (the state is the first machine's, in states too)
    kept_key, kept = info._rows
    if kept_key == key:  # (the interface the same object, or one equal to it)
        return kept
    where = where_line(spec, runtime.state, runtime.mode, states)
    rows = [(f"controls  ({where})" if where else "controls", "")]
    help_key = spec.app_key_table()["help"]
    scene = session.setup.scene.name  # (keys meant for other scenes are left out)
    if show_help:  # the player's controls, the sensors' maps, the app's keys
        rows += control_rows(spec, runtime.state, runtime.mode, scene=scene)
        rows += [("", ""), ("app keys", "")] + app_lines(spec)
    else:  # compact: the maps on one input in one row, a few keys; the rest on help
        rows += control_rows(spec, runtime.state, runtime.mode, f"{help_key}: all", scene)
        rows += [(help_key, "all keys, pose pictures, what the marks mean")]
    info._rows = (key, tuple(rows))  # (not to be changed by the caller)
    return info._rows[1]


def _left_panel(width: int, session: Session, info: HudInfo, font: pygame.font.Font,
                small: pygame.font.Font) -> tuple[list[str], int, list, int]:
    """The top-left panel laid out for a window ``width`` wide: (its lines, its width,
    the how-to-play rows rendered, its height)."""
    setup = session.setup
    keys = session.app_keys
    lines = [
        f"{setup.interface.name}  -  {setup.character.name} on {setup.scene.name}",
        f"sim time {session.time:7.2f} s   step {session.steps}",
        f"slowdown {_fmt_rate(info.slowdown)} (measured {_fmt_rate(info.measured)})",
        f"fps {info.fps:.0f}" if info.fps is not None else "fps -",
    ]
    if info.replaying:
        lines.append(f"REPLAY  {info.replaying}")
    if info.paused:
        lines.append(f"PAUSED  ({keys['step']} steps, {keys['pause']} resumes)")
    changed = world_changes(session)
    if changed:
        lines.append(changed)
    tracker = session.runtime.tracker
    tracking = tracker.status  # mocap: following, pulls, lost
    if tracking and not any(c in session.runtime.channels for c in tracker.joints.values()):
        tracking = f"tracking {tracker.mode}: no motion capture stream"
    if tracking:
        lines.append(tracking)
    for status in info.sources:  # live streams and clips: what came, what was dropped
        lines.append(status)
    if info.playtest:
        lines.append(info.playtest)
    left_w = min(width // 2 - 16,
                 max(300, 16 + max(font.size(text)[0] for text in lines)))  # never clipped
    how = setup.interface.how_to_play  # a newcomer's one line, wrapped under the title
    # (in the panel's width: the character stands just right of it)
    told = _wrapped(small, "how to play: " + how, left_w - 16, info) if how else []
    height = 8 + len(lines) * 22 + len(told) * ROW + (6 if told else 0)
    return lines, left_w, told, height


def _compact_room(width: int, left_w: int) -> int:
    """Pixels the compact controls panel may take: beside the top-left panel, and at
    most COMPACT_SHARE of the window (the character's place stays free)."""
    return min(width - (left_w + 8) - 24, int(COMPACT_SHARE * width))


def top_band(surface: pygame.Surface, session: Session, info: HudInfo,
             font: pygame.font.Font, small: pygame.font.Font) -> int:
    """Pixels from the window's top to below the compact top panels, as ``draw_hud``
    lays them out (without drawing them)."""
    width = surface.get_width()
    _, left_w, _, height = _left_panel(width, session, info, font, small)
    rows = _control_panel(session, info, show_help=False)
    per = max(1, (surface.get_height() - BAR_HEIGHT - 16 - 8 - 8) // ROW)
    _, controls, _ = _lay_out(small, tuple(rows), per, _compact_room(width, left_w))
    return max(8 + height, 8 + controls) + 8


def draw_hud(surface: pygame.Surface, session: Session, info: HudInfo,
             font: pygame.font.Font, small: pygame.font.Font) -> None:
    setup = session.setup
    lines, left_w, told, height = _left_panel(surface.get_width(), session, info, font,
                                              small)
    _panel(surface, pygame.Rect(8, 8, left_w, height))
    surface.blit(text_surface(font, fit(font, lines[0], left_w - 16), TITLE), (16, 12))
    for i, text in enumerate(told):
        surface.blit(text, (16, 12 + 22 + i * ROW))
    below = 12 + len(told) * ROW + (6 if told else 0)
    for i, text in enumerate(lines[1:], start=1):
        surface.blit(text_surface(font, fit(font, text, left_w - 16), TEXT),
                     (16, below + i * 22))

    rows = _control_panel(session, info)
    bottom = surface.get_height() - BAR_HEIGHT - 16
    left = left_w + 8  # the left edge of the room the controls panel has
    if info.show_help:  # what the marks mean, bottom left, above the bar, and the pose
        legend = legend_rows(session)  # keys as pictures, laid out like the keyboard
        drawn = draw_rows(surface, small, legend, None, bottom - 8 - len(legend) * ROW,
                          bottom, surface.get_width() // 2, info._laid)
        space = (surface.get_width() // 2 - 16, drawn.top - 8 - (16 + height))
        keymap = draw_keymap(surface, setup.interface, setup.character, small,
                             (8, 16 + height), state=session.runtime.state, scene=setup.scene,
                             room=space, cache=info._keymap)  # the pictures as large as fit
        # the controls beside them, not over them (room for two columns at least)
        left = max([left, drawn.right] + ([keymap.right] if keymap is not None else []))
        left = min(left, surface.get_width() // 2)
    room = surface.get_width() - left - 24
    if not info.show_help:  # compact: narrow enough to leave the character's place free
        room = _compact_room(surface.get_width(), left_w)
    # (room: the window's width less the top-left panel's - its lines, tracking and
    # sources among them - or, on help, the legend's and the key map's; draw_rows keeps
    # a layout by the room it was laid out for)
    controls = draw_rows(surface, small, rows, surface.get_width() - 8, 8, bottom, room,
                         info._laid)
    if not info.show_help:  # (the help's panels are taller, and only for a while)
        info.top_band = max(8 + height, controls.bottom) + 8
    draw_timeline(surface, session, info, small)
    if info.message:
        draw_message(surface, font, info.message, info.message_error)


MESSAGE_LINES = 8  # a message wraps onto at most this many lines (a long file:line error)


@functools.lru_cache(maxsize=16)
def message_lines(font: pygame.font.Font, text: str, width: int) -> tuple[str, ...]:
    """A message as the HUD lays it out: broken at spaces into lines of at most ``width``
    pixels (a word wider than that - a long path - is broken inside), at most
    MESSAGE_LINES lines. Kept by its arguments: the window draws it every frame."""
    lines, rest = [], text
    while rest and len(lines) < MESSAGE_LINES:
        if font.size(rest)[0] <= width:
            lines.append(rest)
            break
        lo, hi = 1, len(rest)  # the longest prefix that fits
        while lo < hi:
            mid = (lo + hi + 1) // 2
            lo, hi = (mid, hi) if font.size(rest[:mid])[0] <= width else (lo, mid - 1)
        cut = rest.rfind(" ", 0, lo + 1)
        cut = cut if cut > 0 else lo
        lines.append(rest[:cut].rstrip())
        rest = rest[cut:].lstrip()
    return tuple(lines)


def draw_message(surface: pygame.Surface, font: pygame.font.Font, text: str,
                 error: bool) -> pygame.Rect:
    """The session's message (a blow-up, a reload error) above the timeline bar, in the
    middle, wrapped so that nothing of it is cut off."""
    width = surface.get_width() - 48
    lines = message_lines(font, text, width)
    rendered = [font.render(line, True, ERROR if error else NEWS) for line in lines]
    w = max(r.get_width() for r in rendered)
    h = 22 * len(rendered)
    rect = pygame.Rect(0, 0, w, h)
    rect.midbottom = (surface.get_width() // 2, surface.get_height() - BAR_HEIGHT - 10)
    _panel(surface, rect.inflate(16, 8))
    for i, r in enumerate(rendered):
        surface.blit(r, (rect.x, rect.y + i * 22))
    return rect


def _wrapped(small, text: str, width: int, info: HudInfo) -> list:
    """``text`` wrapped to ``width`` and rendered in the news colour, kept in ``info``
    by the text and width (the how-to-play line is drawn every frame)."""
    key = ("how", text, width, small)
    got = info._laid.get(key)
    if got is None:
        got = [small.render(line, True, NEWS) for line in wrap(small, text, width)]
        if len(info._laid) >= LAID_KEPT:
            del info._laid[next(iter(info._laid))]
        info._laid[key] = got
    return got


def frame_under_panels(surface, camera, session: Session, info: HudInfo, font,
                       small) -> None:
    """Give ``camera`` the band the top panels take (a scene's fixed view is framed
    below them); before the first frame, the HUD's panels are laid out to know it."""
    if camera.fixed_y is None:
        return
    if info.top_band is None:  # (then draw_hud keeps it, from what it draws)
        info.top_band = top_band(surface, session, info, font, small)
    camera.reserve_top(info.top_band)


def draw_timeline(surface: pygame.Surface, session: Session, info: HudInfo,
                  small: pygame.font.Font) -> None:
    """A bar along the bottom: the rewindable span (blue), checkpoints (orange ticks),
    automatic checkpoints (grey ticks) and where the simulation is now (dark line),
    between 0 s (left) and the latest time reached (right, labelled)."""
    history = getattr(session, "history", None)
    if history is None:
        return
    dt = session.sim.dt
    span = history.span()
    marks = history.checkpoint_steps()
    branches = history.branches if info.branch is not None else []
    last = max([session.steps] + ([span[1]] if span else []) + marks
               + [b.head for b in branches])
    end = max(last * dt, 1.0)
    w, h = surface.get_size()
    end_label = text_surface(small, f"{end:.1f} s", DIM)
    x0, x1, y = 90, w - 24 - end_label.get_width(), h - 18
    _panel(surface, pygame.Rect(8, y - 12, w - 16, 24))
    label = "REWIND" if info.scrubbing else f"{session.time:6.1f} s"
    surface.blit(text_surface(small, label, TITLE if info.scrubbing else TEXT), (16, y - 7))
    surface.blit(end_label, (x1 + 8, y - 7))

    def px(step: int) -> int:
        return round(x0 + (x1 - x0) * min(1.0, step * dt / end))

    pygame.draw.rect(surface, (215, 218, 224), pygame.Rect(x0, y - 3, x1 - x0, 6))
    if span is not None:
        a, b = px(span[0]), px(span[1])
        pygame.draw.rect(surface, (120, 160, 220), pygame.Rect(a, y - 3, max(2, b - a), 6))
    for snap in history.auto:
        pygame.draw.line(surface, (150, 150, 150), (px(snap.step), y + 3), (px(snap.step), y + 6))
    for step in marks:
        pygame.draw.line(surface, (230, 140, 30), (px(step), y - 8), (px(step), y + 8), 2)
    cur = px(session.steps)
    pygame.draw.line(surface, (20, 30, 50), (cur, y - 9), (cur, y + 9), 3)
    if info.branch is not None:
        draw_branches(surface, session, info, small, px, y)


BRANCH = (130, 60, 170)


def draw_branches(surface, session: Session, info: HudInfo, small, px, y: int) -> None:
    """The branches near now on the timeline bar (each a purple span from its fork to its
    end, numbered; the selected one thick) and a line saying what the keys do."""
    history, keys = session.history, session.app_keys
    near = history.branches_near(session.steps)
    for rank, i in enumerate(near):
        b = history.branches[i]
        a, e = px(b.fork), px(b.head)
        thick = 3 if i == info.branch else 1
        pygame.draw.line(surface, BRANCH, (a, y - 11 - thick), (max(e, a + 2), y - 11 - thick),
                         thick)
        pygame.draw.line(surface, BRANCH, (a, y - 11 - thick), (a, y - 4), 1)
        surface.blit(small.render(str(rank + 1), True, BRANCH), (a + 2, y - 30))
    if info.branch is not None and info.branch < len(history.branches):
        b = history.branches[info.branch]
        dt = session.sim.dt
        text = (f"branch {near.index(info.branch) + 1 if info.branch in near else '?'} of "
                f"{len(near)}: from {b.fork * dt:.1f} s, {b.steps * dt:.1f} s long - "
                f"{keys['take_branch']} takes it up, {keys['export_branch']} exports it, "
                f"{keys['branches']} the next")
        label = small.render(fit(small, text, surface.get_width() - 40), True, BRANCH)
        rect = label.get_rect(bottomleft=(16, y - 34))
        _panel(surface, rect.inflate(10, 6))
        surface.blit(label, rect)
