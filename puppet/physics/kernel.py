"""The compiled kernel: the control layer's per-tick arithmetic in C, to the bit.

KD tracking's pulls (forward kinematics of the performed pose, the pull loop over the
links, the joint targets) and the centre of mass with its velocity cost 10-30 us of
Python a control step against a 15-75 us physics step; the same work in C costs about
a microsecond. Frame targets (``pk_frame``), the support polygon's extent
(``pk_support``: the contacts' x, without a Python callback a contact) and a two-link
chain's IK (``pk_two_link``: a reach's solve at every step) are in it too.
``kernel_source`` holds the C, written operation for operation as the Python it
replaces, so a log replays to its recorded hash either way.

It is a cffi module in API mode (pymunk depends on cffi already), compiled on first
use into the user's cache: ``$XDG_CACHE_HOME/puppet`` (``~/.cache/puppet``), under a
name keyed by a hash of the C text, the compiler flags, the Python ABI and the
platform, so another version of puppet or of Python builds its own. It is compiled in
a temporary directory and moved into place with one rename, so two processes that
build it at once do not collide. Without a C compiler (or with ``PUPPET_KERNEL=
python``) the pure-Python code runs, giving the same bits: ``get()`` is then None.
``PUPPET_KERNEL=c`` makes a failed build an error instead of a fallback.
"""

from __future__ import annotations

import os
import sys

from puppet.physics.kernel_source import CDEF, SOURCE

# no contraction into fused multiply-adds, no reassociation, no sincos (kernel_source)
FLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-builtin", "-fno-strict-aliasing"]
ENV = "PUPPET_KERNEL"  # "python": the pure-Python path; "c": the kernel or an error
# pymunk's Chipmunk calls the kernel makes, in pk_init's order
FUNCTIONS = ("cpBodyGetPosition", "cpBodyGetAngle", "cpBodyGetVelocity",
             "cpBodyGetAngularVelocity", "cpBodyGetMoment", "cpBodySetVelocity",
             "cpBodySetAngularVelocity", "cpDampedRotarySpringSetRestAngle",
             "cpBodyEachArbiter", "cpArbiterGetContactPointSet")

_loaded: list = []  # [Kernel or None] once tried


class KernelError(RuntimeError):
    """``PUPPET_KERNEL=c`` and the kernel could not be built or loaded."""


class Kernel:
    """The loaded module: ``ffi``, ``lib``, and ``pointer`` to hand it pymunk's C
    objects."""

    def __init__(self, module):
        from pymunk._chipmunk_cffi import ffi as pffi
        from pymunk._chipmunk_cffi import lib as plib

        self.ffi, self.lib = module.ffi, module.lib
        self._as_int = lambda cdata: int(pffi.cast("uintptr_t", cdata))
        fns = self.ffi.new("void *[]", [self.pointer(pffi.addressof(plib, name))
                                        for name in FUNCTIONS])
        self.lib.pk_init(fns)

    def pointer(self, cdata):
        """A pymunk cdata pointer (``body._body``, ``spring._constraint``) as the
        kernel's ``void *``."""
        return self.ffi.cast("void *", self._as_int(cdata))


def mode() -> str:
    """``PUPPET_KERNEL``: "python", "c" or "" (the kernel when it builds)."""
    return os.environ.get(ENV, "").strip().lower()


def get() -> Kernel | None:
    """The kernel, built or loaded once per process; None on the pure-Python path."""
    if not _loaded:
        _loaded.append(_load())
    return _loaded[0]


def reset() -> None:
    """Forget the loaded kernel (tests switch ``PUPPET_KERNEL``; objects made before
    keep theirs)."""
    _loaded.clear()


def key() -> str:
    """The build's name: a hash of what makes a different binary."""
    import hashlib
    import sysconfig

    import _cffi_backend  # (cffi's C part, which pymunk has loaded: its version, cheaply)

    text = "\n".join([CDEF, SOURCE, " ".join(FLAGS), sys.implementation.cache_tag,
                      sys.version, sysconfig.get_platform(), _cffi_backend.__version__])
    return "_puppet_kernel_" + hashlib.sha256(text.encode()).hexdigest()[:16]


def cache_dir() -> str:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "puppet")


def _load() -> Kernel | None:
    how = mode()
    if how == "python":
        return None
    try:
        return Kernel(_module())
    except Exception as exc:  # noqa: BLE001 - no compiler, no cache: Python's path
        if how == "c":
            raise KernelError(f"{ENV}=c: the compiled kernel: {exc}") from exc
        return None


def _module():
    import importlib.machinery
    import importlib.util
    import sysconfig

    name = key()
    where = cache_dir()
    path = os.path.join(where, name + sysconfig.get_config_var("EXT_SUFFIX"))
    failed = os.path.join(where, name + ".failed")
    if not os.path.exists(path):
        if os.path.exists(failed) and mode() != "c":
            raise RuntimeError(f"an earlier build failed (see {failed})")
        _build(name, where, path, failed)
    loader = importlib.machinery.ExtensionFileLoader(name, path)
    spec = importlib.util.spec_from_file_location(name, path, loader=loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def _build(name: str, where: str, path: str, failed: str) -> None:
    """Compile into a temporary directory, then rename into place (atomic: a process
    that built it at the same time renames the same bytes)."""
    import shutil
    import tempfile

    import cffi

    os.makedirs(where, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=name + ".", dir=where)
    try:
        ffi = cffi.FFI()
        ffi.cdef(CDEF)
        ffi.set_source(name, SOURCE, libraries=["m"], extra_compile_args=FLAGS)
        try:
            built = ffi.compile(tmpdir=tmp, verbose=False)
        except Exception as exc:
            with open(failed, "w") as f:  # no compiler: do not try at every start
                f.write(f"{type(exc).__name__}: {exc}\n")
            raise
        os.replace(built, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
