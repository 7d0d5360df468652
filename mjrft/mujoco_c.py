"""MuJoCo's C functions called from compiled code: the library the bindings loaded, the addresses of its
functions, and the numba intrinsics that call a function at such an address.

The fused stepping loop (:func:`mjrft.stepping.run_steps`), the implicit step (:mod:`mjrft.implicit_step`) and the
stability check (:mod:`mjrft.stability`) call ``mj_step1``, ``mj_step2``, ``mj_jacBodyCom``, ``mj_solveM`` and
the like without going back to Python. The addresses are passed to the compiled functions as arguments at run
time, so the compiled code stays cacheable. The library is the one the ``mujoco`` package ships next to its
bindings (:func:`find_library`); when it is not found the callers fall back to the Python bindings (or, for the
implicit step, refuse it).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import fnmatch
import os
import sys

from llvmlite import ir
from numba import types
from numba.extending import intrinsic

#: file-name patterns of the MuJoCo library inside the ``mujoco`` package, per platform (how the mujoco wheels
#: ship it: ``libmujoco.so.<version>`` on Linux, ``libmujoco.<version>.dylib`` on macOS, ``mujoco.dll`` on Windows)
LIBRARY_PATTERNS = {
    "linux": ("libmujoco.so.*", "libmujoco.so"),
    "darwin": ("libmujoco.*.dylib", "libmujoco.dylib"),
    "windows": ("mujoco.dll",),
}


def platform_key(platform: str | None = None) -> str:
    """The key of :data:`LIBRARY_PATTERNS` for ``platform`` (default ``sys.platform``): ``"darwin"``, ``"windows"``
    (``win32``, ``cygwin``) or ``"linux"`` (every other platform: ELF shared objects)."""
    platform = sys.platform if platform is None else platform
    if platform.startswith("darwin"):
        return "darwin"
    if platform.startswith(("win", "cygwin")):
        return "windows"
    return "linux"


def library_in(folder: str, platform: str | None = None) -> str | None:
    """Path of the MuJoCo library in ``folder`` by ``platform``'s file names (:data:`LIBRARY_PATTERNS`), or None.
    With several matches the first pattern wins, and within it the first name in sorted order."""
    try:
        names = sorted(os.listdir(folder))
    except OSError:
        return None
    for pattern in LIBRARY_PATTERNS[platform_key(platform)]:
        found = [n for n in names if fnmatch.fnmatchcase(n, pattern)]
        if found:
            return os.path.join(folder, found[0])
    return None


def find_library(folder: str | None = None, platform: str | None = None) -> str | None:
    """Path of the MuJoCo library the ``mujoco`` bindings use, or None: the platform's file (:func:`library_in`)
    in ``folder`` (default: the ``mujoco`` package's folder, where its wheels put it next to the ``_functions``
    extension that links it), else, for the default folder, the library the system's loader finds by name
    (``ctypes.util.find_library("mujoco")``: a build of the bindings against an installed MuJoCo)."""
    if folder is not None:
        return library_in(folder, platform)
    import mujoco

    return library_in(os.path.dirname(mujoco.__file__), platform) or ctypes.util.find_library("mujoco")


def mujoco_functions(*names: str) -> tuple[int, ...] | None:
    """Addresses of MuJoCo's C functions ``names`` in the library the bindings loaded (:func:`find_library`), or
    None when the library or one of the functions is not found."""
    path = find_library()
    if path is None:
        return None
    try:
        lib = ctypes.CDLL(path)
        return tuple(ctypes.cast(getattr(lib, n), ctypes.c_void_p).value for n in names)
    except (OSError, AttributeError):
        return None


def mujoco_step_functions() -> tuple[int, int] | None:
    """Addresses of MuJoCo's ``mj_step1`` and ``mj_step2`` (:func:`mujoco_functions`), or None."""
    return mujoco_functions("mj_step1", "mj_step2")


@intrinsic
def call_mj(typingctx, fptr, m_addr, d_addr):
    """Call ``void f(const mjModel*, mjData*)`` at address ``fptr`` (compiled code only)."""
    sig = types.void(types.intp, types.intp, types.intp)

    def codegen(context, builder, signature, args):
        f, a, b = args
        vp = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [vp, vp])
        fn = builder.inttoptr(f, fnty.as_pointer())
        builder.call(fn, [builder.inttoptr(a, vp), builder.inttoptr(b, vp)])
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def call_mj_arrays(typingctx, fptr, m_addr, d_addr, a_addr, b_addr, n):
    """Call ``void f(const mjModel*, mjData*, mjtNum* a, mjtNum* b, int n)`` at address ``fptr`` (the shape of
    both ``mj_jacBodyCom(m, d, jacp, jacr, body)`` and ``mj_solveM(m, d, x, y, n)``; compiled code only)."""
    sig = types.void(types.intp, types.intp, types.intp, types.intp, types.intp, types.intp)

    def codegen(context, builder, signature, args):
        f, m, d, a, b, k = args
        vp, dp, i32 = ir.IntType(8).as_pointer(), ir.DoubleType().as_pointer(), ir.IntType(32)
        fn = builder.inttoptr(f, ir.FunctionType(ir.VoidType(), [vp, vp, dp, dp, i32]).as_pointer())
        builder.call(fn, [builder.inttoptr(m, vp), builder.inttoptr(d, vp), builder.inttoptr(a, dp),
                          builder.inttoptr(b, dp), builder.trunc(k, i32)])
        return context.get_dummy_value()

    return sig, codegen
