"""Shared by the compiled kernel's tests: ``needs_cc`` skips where no C compiler is on
the PATH (the ``path_of`` fixture, which switches a test between the kernel and the
pure-Python path, is in conftest.py)."""

from __future__ import annotations

import os
import shutil

import pytest

needs_cc = pytest.mark.skipif(shutil.which(os.environ.get("CC", "cc")) is None
                              and shutil.which("gcc") is None, reason="no C compiler")
