"""Opening the window's display, and saying what to run instead when there is none.

SDL falls back to an off-screen driver without a display, where a window would run
invisibly for ever; these helpers refuse that with a one-line hint (the headless
command), and keep SDL's own stderr lines until it is known whether they matter.
"""

from __future__ import annotations

import contextlib
import os
import shlex
import sys
import tempfile
import warnings
from pathlib import Path

from puppet.data.errors import UsageError

MIN_SIZE = (1024, 640)

HEADLESS_HINT = ("use --headless to run without a window (e.g. puppet play luxo-mouse "
                 "--headless --input luxo-hop --screenshot out.png)")
OFFSCREEN_DRIVERS = ("offscreen", "dummy")


def headless_hint(replay=None) -> str:
    """What to run instead without a display: ``puppet play`` 's headless example, or
    for a replay (``replay``: its ``Log``) the same replay headless: the log by its
    bare name if that name finds this very file (``find_log``: assets/logs/ is searched
    before recordings/, so recordings/luxo-hop.jsonl is not 'luxo-hop' when
    assets/logs/luxo-hop.jsonl exists), else its path, quoted for the shell."""
    if replay is None:
        return HEADLESS_HINT
    from puppet.data.errors import DataError
    from puppet.timeline.replay import find_log

    path = Path(replay.path)
    try:
        named = Path(find_log(path.stem)).resolve() == path.resolve()
    except (DataError, OSError):
        named = False
    log = path.stem if named else _quoted(str(replay.path))
    return (f"use --headless to replay without a window (e.g. puppet replay {log} "
            f"--headless, or add --video out.mp4 to see it)")


@contextlib.contextmanager
def _held_stderr():
    """Hold what is written to the process's stderr (file descriptor 2, where SDL's C
    code writes: "error: XDG_RUNTIME_DIR is invalid or not set" before the no-display
    line) until the block ends; yields a list that then holds the text."""
    said: list[str] = []
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):  # no real stderr (an embedding): nothing to hold
        yield said
        return
    with tempfile.TemporaryFile() as held:
        os.dup2(held.fileno(), 2)
        try:
            yield said
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            held.seek(0)
            said.append(held.read().decode("utf-8", "replace"))
    if not said[0]:
        said.clear()


def _quoted(text: str) -> str:
    """A path as the user's shell takes it: POSIX quoting, or on Windows double quotes
    around a path with a space or a character cmd.exe or PowerShell treat specially
    (neither reads POSIX single quotes)."""
    if os.name == "nt":
        return f'"{text}"' if any(c in text for c in ' &()^;,\'') else text
    return shlex.quote(text)


def no_display(pygame, hint: str = HEADLESS_HINT) -> str:
    """Why no window can be seen ("" if one can). Without a display SDL falls back to
    an off-screen video driver, and the window would run, invisibly, for ever. A
    driver asked for by name (SDL_VIDEODRIVER=dummy, as the tests do) is the user's
    choice."""
    try:
        driver = pygame.display.get_driver()
    except pygame.error:
        driver = ""
    asked = os.environ.get("SDL_VIDEODRIVER", "").strip().lower()
    if driver and (driver not in OFFSCREEN_DRIVERS or asked == driver):
        return ""
    return f"no display found (SDL could only open its '{driver or 'none'}' video driver); " \
           f"{hint}"


def open_display(size, title: str, hint: str):
    """pygame with a resizable window titled ``title`` (a ``UsageError`` when no
    display can be seen: ``hint`` says what to run instead)."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    with _held_stderr() as said:  # what SDL prints while it looks for a display
        try:
            pygame.display.init()  # no pygame.init(): puppet makes no sound
            missing = no_display(pygame, hint)
        except pygame.error as exc:
            missing = f"no display found ({exc}); {hint}"
    if missing:  # before anything is recorded; SDL's own lines would only come first
        pygame.quit()
        raise UsageError(missing)
    if said:  # a display was found: SDL's words may matter (a driver's warning)
        sys.stderr.write(said[0])
    pygame.font.init()
    pygame.joystick.init()  # gamepads arrive as JOYDEVICEADDED events (hot-plug)
    screen = pygame.display.set_mode(size, pygame.RESIZABLE)
    try:  # pygame-ce: the display's Window object carries the title and a minimum size
        with warnings.catch_warnings():  # we draw through pygame.display, knowingly
            warnings.simplefilter("ignore", DeprecationWarning)
            window = pygame.Window.from_display_module()
        window.title = title
        window.minimum_size = MIN_SIZE
    except (AttributeError, pygame.error):
        pygame.display.set_caption(title)
    return pygame, screen
