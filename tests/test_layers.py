"""Every import inside puppet points down the layers, and no two packages import each other.

The layers, bottom to top (docs/architecture.md):

    data -> physics -> interface -> input -> mocap -> session -> timeline -> app -> commands

with ``puppet/testing.py`` (the API for test authors) and ``puppet/__main__.py`` on top,
and the root package (``puppet/__init__.py``: the version) at the bottom. A module may
import its own layer and the layers below it, never one above. Every import is read with
``ast``: at module level, inside functions (the lazy imports that keep the command line
fast) and under ``if TYPE_CHECKING``, relative imports too.

The packages of puppet (data, physics, ..., commands; testing.py and __main__.py count as
one each) must not form a cycle: ``a`` importing ``b`` while ``b`` imports ``a``,
directly or around a longer loop. (Inside a package, its sub-packages and modules may
use each other: ``interface/runtime.py`` runs the ``interface/controllers/``, which
read ``interface/ownership.py``.) With every import pointing down no cycle can form
between layers; the check stays as a second guard, and names the imports that close
the loop.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

PUPPET = Path(__file__).resolve().parents[1] / "puppet"

LAYERS = ("data", "physics", "interface", "input", "mocap", "session", "timeline", "app",
          "commands")
TOP = ("testing", "__main__")  # the modules on top of everything


def module_name(path: Path, root: Path = PUPPET) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def layer(module: str) -> int:
    """The rank of a puppet module's layer: 0 the root package, then LAYERS, then TOP."""
    parts = module.split(".")
    if len(parts) == 1:
        return 0
    if parts[1] in LAYERS:
        return 1 + LAYERS.index(parts[1])
    if parts[1] in TOP:
        return 1 + len(LAYERS)
    raise AssertionError(f"{module}: in no layer; add puppet/{parts[1]} to LAYERS in "
                         f"{Path(__file__).name} (where it belongs in the flow)")


def package(module: str) -> str:
    """The top-level package a module is in: ``puppet.timeline`` for
    ``puppet.timeline.log``; ``puppet.testing`` for itself, ``puppet`` for the root."""
    return ".".join(module.split(".")[:2])


def puppet_modules(root: Path = PUPPET) -> dict[str, Path]:
    return {module_name(p, root): p for p in sorted(root.rglob("*.py"))}


@functools.cache
def _statements(text: str, here: str) -> tuple[tuple[str, tuple[str, ...], bool, int], ...]:
    """The import statements of a module's text (``here``: its package), each as
    (absolute module, names, names are from it, line); parsed once per text."""
    out = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            out += [(a.name, (), False, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:  # relative: from the package, up level - 1 packages
                parts = here.split(".")
                parts = parts[:len(parts) - (node.level - 1)]
                base = ".".join(parts + ([base] if base else []))
            out.append((base, tuple(a.name for a in node.names), True, node.lineno))
    return tuple(out)


def imports(root: Path = PUPPET) -> list[tuple[str, str, int]]:
    """(importing module, imported puppet module, line) for every import in puppet/.
    ``from a.b import c`` names ``a.b.c`` when that is a module, else ``a.b``."""
    modules = puppet_modules(root)
    out = []
    for name, path in modules.items():
        here = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for base, names, from_, line in _statements(path.read_text(encoding="utf-8"), here):
            targets = ([f"{base}.{n}" if f"{base}.{n}" in modules else base for n in names]
                       if from_ else [base])
            out += [(name, t, line) for t in targets if t.split(".")[0] == "puppet"]
    return out


def upward(root: Path = PUPPET) -> list[str]:
    """Every import of a higher layer, as ``file:line: a imports b (layer x above y)``."""
    modules = puppet_modules(root)
    found = []
    for src, dst, line in imports(root):
        if layer(dst) > layer(src):
            found.append(f"{modules[src].relative_to(root.parent)}:{line}: {src} imports "
                         f"{dst} ({_layer_name(dst)} is above {_layer_name(src)})")
    return found


def _layer_name(module: str) -> str:
    parts = module.split(".")
    return "puppet" if len(parts) == 1 else parts[1]


def package_cycles(root: Path = PUPPET) -> list[str]:
    """Each cycle of packages importing each other, with the imports that make it."""
    modules = puppet_modules(root)
    edges: dict[str, dict[str, str]] = {}  # package -> package -> one import that does it
    for src, dst, line in imports(root):
        a, b = package(src), package(dst)
        if a != b:
            edges.setdefault(a, {}).setdefault(
                b, f"{modules[src].relative_to(root.parent)}:{line} imports {dst}")
    # strongly connected components (Tarjan): a component of two or more is a cycle
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in edges.get(v, {}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return [" <-> ".join(c) + ": " + "; ".join(edges[a][b] for a in c for b in c
                                               if b in edges.get(a, {}))
            for c in components]


def test_every_module_is_in_a_layer():
    for name in puppet_modules():
        layer(name)


def test_no_import_points_up():
    found = upward()
    assert not found, "imports of a higher layer:\n" + "\n".join(found)


def test_no_packages_import_each_other():
    found = package_cycles()
    assert not found, "packages in a cycle:\n" + "\n".join(found)


@pytest.fixture
def tree(tmp_path):
    """A copy of puppet/ to add imports to."""
    import shutil

    copy = tmp_path / "puppet"
    shutil.copytree(PUPPET, copy, ignore=shutil.ignore_patterns("__pycache__"))
    return copy


def _append(path: Path, text: str) -> None:
    path.write_text(path.read_text(encoding="utf-8") + text, encoding="utf-8")


def test_an_upward_import_is_found_and_named(tree):
    """At module level, inside a function, relative: each is named with its line."""
    _append(tree / "physics" / "servo.py", "\nfrom puppet.session import Session\n")
    _append(tree / "data" / "keys.py", "\n\ndef f():\n    import puppet.app.window\n")
    _append(tree / "interface" / "maps.py", "\nfrom ..timeline import log\n")
    found = upward(tree)
    assert len(found) == 3, found
    servo_line = len((tree / "physics" / "servo.py").read_text().splitlines())
    assert found[0].startswith("puppet/data/keys.py:") and "puppet.app.window" in found[0]
    assert any(f.startswith(f"puppet/physics/servo.py:{servo_line}: puppet.physics.servo "
                            "imports puppet.session (session is above physics)")
               for f in found), found
    assert any("puppet.interface.maps imports puppet.timeline.log" in f for f in found), found


def test_a_cycle_is_found_and_its_imports_named(tree):
    """The Session reaching back into the timeline (as it did before its history moved
    into puppet/session/): the two packages in a cycle, with the imports that make it."""
    _append(tree / "session" / "history.py", "\nfrom puppet.timeline.log import Log\n")
    found = package_cycles(tree)
    assert len(found) == 1, found
    assert found[0].startswith("puppet.session <-> puppet.timeline: "), found
    assert "puppet/session/history.py:" in found[0] and "imports puppet.timeline.log" in found[0]
    assert "puppet/timeline/" in found[0] and "imports puppet.session" in found[0]
