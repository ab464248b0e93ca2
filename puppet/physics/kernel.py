"""The compiled kernel: the control layer's per-tick arithmetic in C, to the bit.

KD tracking's pulls (forward kinematics of the performed pose, the pull loop over the
links, the joint targets) and the centre of mass with its velocity cost 10-30 us of
Python a control step against a 15-75 us physics step; the same work in C costs about
a microsecond. Frame targets (``pk_frame``), the support polygon's extent
(``pk_support``: the contacts' x, without a Python callback a contact) and a two-link
chain's IK (``pk_two_link``: a reach's solve at every step, with the reach's eased
point and its writes: ``pk_reach_aim``, ``pk_reach_set``) are in it too.
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

import math
import os
import sys
import sysconfig

from puppet.physics.kernel_health import HEALTH_CDEF, HEALTH_SOURCE
from puppet.physics.kernel_maps import MAPS_CDEF, MAPS_SOURCE
from puppet.physics.kernel_poll import POLL_CDEF, POLL_SOURCE
from puppet.physics.kernel_source import CDEF as _CDEF
from puppet.physics.kernel_source import SOURCE as _SOURCE

CDEF, SOURCE = _CDEF + MAPS_CDEF, _SOURCE + MAPS_SOURCE  # (pose grids: kernel_maps)
CDEF, SOURCE = CDEF + POLL_CDEF, SOURCE + POLL_SOURCE  # (the stepping loop: kernel_poll,
# whose event runs run pose grids)
CDEF, SOURCE = CDEF + HEALTH_CDEF, SOURCE + HEALTH_SOURCE  # (the health check: kernel_health)

# no contraction into fused multiply-adds, no reassociation, no sincos (kernel_source)
FLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-builtin", "-fno-strict-aliasing"]
if sys.maxsize < 2**32 and any(x in sysconfig.get_platform() for x in ("i386", "i686", "x86")):
    FLAGS += ["-msse2", "-mfpmath=sse"]  # 32-bit x86: doubles in SSE, as x86-64 (not x87)
RETRY_AFTER = 24 * 3600  # s: a failed build is tried again after this (or a new compiler)
ENV = "PUPPET_KERNEL"  # "python": the pure-Python path; "c": the kernel or an error
# pymunk's Chipmunk calls the kernel makes, in pk_init's order
FUNCTIONS = ("cpBodyGetPosition", "cpBodyGetAngle", "cpBodyGetVelocity",
             "cpBodyGetAngularVelocity", "cpBodyGetMoment", "cpBodySetVelocity",
             "cpBodySetAngularVelocity", "cpDampedRotarySpringSetRestAngle",
             "cpBodyEachArbiter", "cpArbiterGetContactPointSet",
             "cpDampedRotarySpringGetRestAngle", "cpBodyLocalToWorld",
             "cpBodyGetCenterOfGravity")

# kernel_source's copy of Chipmunk's cpContactPointSet (pymunk 7.x): size, the offsets
# of normal and points, the points' count and size; another layout keeps Python's path
POINT_SET = (104, 8, 24, 2, 40)
_loaded: list = []  # [Kernel or None] once tried


def cos(a: float) -> float:
    """``math.cos`` as C's ``cos`` answers a blown-up state, where Python raises
    ValueError: a NaN (``a - a``: the processor's NaN for +-inf, a NaN passed on). The
    Python path must not crash where the kernel goes on to the session's blow-up check,
    which restores a checkpoint. (The NaN's sign bit may still differ from the kernel's
    after further arithmetic; no hash of a blown-up state is ever judged.)"""
    return math.cos(a) if a - a == 0.0 else a - a


def sin(a: float) -> float:
    """``math.sin``, likewise."""
    return math.sin(a) if a - a == 0.0 else a - a


def remainder(x: float, y: float) -> float:
    """``math.remainder``, likewise for a non-finite ``x`` (``y`` is a finite turn)."""
    return math.remainder(x, y) if x - x == 0.0 else x - x


def nearest(q: float) -> float:
    """``round(q)`` (half to even) as C's ``nearbyint``: NaN and +-inf stay themselves,
    where Python's ``round`` raises."""
    return round(q) if q - q == 0.0 else q


class KernelError(RuntimeError):
    """``PUPPET_KERNEL=c`` and the kernel could not be built or loaded."""


class Kernel:
    """The loaded module: ``ffi``, ``lib``, and ``pointer`` to hand it pymunk's C
    objects."""

    def __init__(self, module):
        from pymunk._chipmunk_cffi import ffi as pffi
        from pymunk._chipmunk_cffi import lib as plib

        points = pffi.typeof("cpContactPointSet").fields[2][1].type
        layout = (pffi.sizeof("cpContactPointSet"), pffi.offsetof("cpContactPointSet", "normal"),
                  pffi.offsetof("cpContactPointSet", "points"), points.length,
                  pffi.sizeof(points.item))
        if layout != POINT_SET:  # pk_support receives it by value: a larger one would
            raise RuntimeError(f"this pymunk's cpContactPointSet {layout} is not the "
                               f"kernel's {POINT_SET}")  # overrun the kernel's stack
        self.ffi, self.lib = module.ffi, module.lib
        self._as_int = lambda cdata: int(pffi.cast("uintptr_t", cdata))
        fns = self.ffi.new("void *[]", [self.pointer(pffi.addressof(plib, name))
                                        for name in FUNCTIONS])
        self.lib.pk_init(fns)
        self.lib.pk_poll_init(self.pointer(pffi.addressof(plib, "cpSpaceStep")))

    def pointer(self, cdata):
        """A pymunk cdata pointer (``body._body``, ``spring._constraint``) as the
        kernel's ``void *``."""
        return self.ffi.cast("void *", self._as_int(cdata))


def remembered(kern: Kernel, memo: dict, cdata):
    """``kern.pointer(cdata)``, kept in ``memo`` for the next ask (the poll plans and the
    event runs fill their tables with the same bodies and springs again and again; a
    restore makes new ones, so the memo is bounded: cleared past 256)."""
    got = memo.get(cdata)
    if got is None:
        if len(memo) > 256:
            memo.clear()
        got = memo[cdata] = kern.pointer(cdata)
    return got


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
    name = key()
    where = cache_dir()
    path = os.path.join(where, name + sysconfig.get_config_var("EXT_SUFFIX"))
    failed = os.path.join(where, name + ".failed")
    if not _intact(path):  # (absent, cut short, or another build's bytes)
        if mode() != "c" and _failed_before(failed):
            raise RuntimeError(f"an earlier build failed (see {failed})")
        _build(name, where, path, failed)
    try:
        return _load_module(name, path)
    except ImportError:  # intact bytes that do not load (another Python's?): once more
        _build(name, where, path, failed)
        return _load_module(name, path)


def _load_module(name: str, path: str):
    import importlib.machinery
    import importlib.util

    loader = importlib.machinery.ExtensionFileLoader(name, path)
    spec = importlib.util.spec_from_file_location(name, path, loader=loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def _digest(path: str) -> str:
    import hashlib

    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def _intact(path: str) -> bool:
    """The module is there with the bytes its build wrote down (``.sha256``): a file
    cut short by a crash or a full disk is never loaded (that would be SIGBUS)."""
    try:
        with open(path + ".sha256") as f:
            return f.read().strip() == _digest(path)
    except OSError:
        return False


def _compiler() -> str:
    """What decides whether a build can work: ``CC`` and the compilers on the PATH."""
    import shutil

    return " ".join(str(x) for x in (os.environ.get("CC"), shutil.which("cc"),
                                     shutil.which("gcc"), shutil.which("clang")))


def _failed_before(failed: str) -> bool:
    """An earlier build failed with the same compilers, less than a day ago: do not try
    at every start (a compiler installed since, or a day gone, tries again)."""
    import time

    try:
        with open(failed) as f:
            first = f.readline().rstrip("\n")
        return first == _compiler() and time.time() - os.path.getmtime(failed) < RETRY_AFTER
    except OSError:
        return False


def _build(name: str, where: str, path: str, failed: str) -> None:
    """Compile into a temporary directory, write it to disk, then rename it into place
    with its digest beside it (a process building at the same time renames its own
    whole file; a digest that does not match makes the next start build again)."""
    import shutil
    import tempfile
    import time

    import cffi

    os.makedirs(where, exist_ok=True)
    for old in os.listdir(where):  # a build killed midway left its directory
        full = os.path.join(where, old)
        if old.startswith(name + ".") and os.path.isdir(full) \
                and time.time() - os.path.getmtime(full) > 3600:
            shutil.rmtree(full, ignore_errors=True)
    tmp = tempfile.mkdtemp(prefix=name + ".", dir=where)
    try:
        ffi = cffi.FFI()
        ffi.cdef(CDEF)
        ffi.set_source(name, SOURCE, libraries=[] if sys.platform == "win32" else ["m"],
                       extra_compile_args=FLAGS)
        try:
            built = ffi.compile(tmpdir=tmp, verbose=False)
        except Exception as exc:
            with open(failed, "w") as f:  # no compiler: not tried again at every start
                f.write(f"{_compiler()}\n{type(exc).__name__}: {exc}\n")
            raise
        digest = _digest(built)
        with open(built, "rb") as f:
            os.fsync(f.fileno())
        with open(os.path.join(tmp, "digest"), "w") as f:
            f.write(digest + "\n")
            f.flush()
            os.fsync(f.fileno())
        os.replace(built, path)
        os.replace(os.path.join(tmp, "digest"), path + ".sha256")
        if os.path.exists(failed):
            os.remove(failed)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
