"""The key vocabulary in puppet/data/keys.py is pure data: validating a data file needs
neither pygame nor the interface runtime, and its copy of pygame's key names is the
installed pygame's."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import warnings

from puppet.data.keys import PYGAME_KEY_NAMES, key_problem


def test_key_name_table_is_what_pygame_names_its_keys():
    """Fails when pygame (an upgrade) names its keys otherwise than the literal table:
    regenerate ``PYGAME_KEY_NAMES`` with the expression below and check the shipped
    interfaces and scripts still load (``puppet check``)."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    with warnings.catch_warnings():  # names need no display, so no pygame.init()
        warnings.simplefilter("ignore")
        names = frozenset(pygame.key.name(getattr(pygame, c)).lower() for c in dir(pygame)
                          if c.startswith("K_")) - {""}
    assert sorted(names - PYGAME_KEY_NAMES) == [], "pygame names keys the table lacks"
    assert sorted(PYGAME_KEY_NAMES - names) == [], "the table names keys pygame does not"


def test_a_key_is_checked_against_the_table():
    assert key_problem("ctrl+page up") is None
    assert key_problem("[*]") is None  # the keypad's times, as pygame names it
    assert key_problem("gamepad.dpad_up") is None and key_problem("mouse.left") is None
    assert "unknown key name 'pageup'" in key_problem("pageup")


def test_data_modules_import_neither_pygame_nor_the_interface():
    """Import every module of puppet.data in a fresh interpreter and load every shipped
    interface with its character and scene (key names checked); then neither pygame nor
    any puppet.interface module (nor the app, timeline, physics) may have been loaded."""
    code = textwrap.dedent("""
        import importlib, pkgutil, sys
        import puppet.data
        for m in pkgutil.iter_modules(puppet.data.__path__):
            importlib.import_module("puppet.data." + m.name)
        from puppet.data.catalog import find, list_kind, load_setup
        from puppet.data.keys import key_problem
        names = [n for n, _ in list_kind("interface")]
        assert len(names) >= 5, names
        for name in names:
            load_setup(str(find("interface", name)))
        assert key_problem("ctrl+a") is None and key_problem("nokey")
        bad = sorted(m for m in sys.modules if m.split(".")[0] == "pygame"
                     or m.startswith(("puppet.interface", "puppet.app", "puppet.timeline",
                                      "puppet.physics", "puppet.session")))
        print(len(names), bad)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60)
    assert out.returncode == 0, out.stderr
    count, _, bad = out.stdout.strip().partition(" ")
    assert int(count) >= 5
    assert bad == "[]", f"puppet.data pulled in: {bad}"
