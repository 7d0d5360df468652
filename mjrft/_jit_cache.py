"""Where numba caches mjrft's compiled kernels.

numba invalidates a cached function only when its own source file changes, not when a function it
calls (in another file) does, so a stale kernel could survive an edit or upgrade of a force law.
We therefore cache under a folder named after a hash of the sources compiled code can depend on:
every file of mjrft that mentions numba, plus ``media.py`` (the parameter-vector layout the laws
index), ``laws/registry.py`` (the table of laws the compiled dispatch is generated from) and this file.
``$MJRFT_CACHE_DIR`` (default ``~/.cache/mjrft``) / ``numba-<hash>``. Editing pure-Python modules (the
coupler, the CLI) therefore keeps the cache. Must run before any
``@njit(cache=True)`` in mjrft is decorated.
"""

from __future__ import annotations

import hashlib
import os
import threading
import types
from pathlib import Path

import numba


ROOT = Path(__file__).resolve().parent


def _sources():
    """(path relative to the package, its bytes) of every source file of mjrft."""
    for path in sorted(ROOT.rglob("*.py")):
        yield path.relative_to(ROOT), path.read_bytes()


def configure() -> str:
    h = hashlib.sha1(numba.__version__.encode())
    for rel, text in _sources():
        if b"numba" in text or rel.as_posix() in ("media.py", "laws/registry.py"):
            h.update(str(rel).encode())
            h.update(text)
    base = Path(os.environ.get("MJRFT_CACHE_DIR", Path.home() / ".cache" / "mjrft"))
    folder = base / f"numba-{h.hexdigest()[:16]}"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:  # read-only home: fall back to numba's own default next to the sources
        return numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(folder)
    return str(folder)


CACHE_DIR = configure()



def compiled_modules() -> list[str]:
    """The modules of mjrft that compile functions with numba (their source calls ``njit``)."""
    return ["mjrft." + rel.with_suffix("").as_posix().replace("/", ".") for rel, text in _sources()
            if b"njit(" in text and rel.name != "__init__.py"]

_loaded = None  # how many cached overloads load_cached_callees_first loaded (None: not run yet)
_loading = threading.Lock()


def callees_first(functions) -> list:
    """``functions`` (numba dispatchers) and every dispatcher their code names, directly or through those,
    ordered so that each comes after every dispatcher it calls."""
    from numba.core.registry import CPUDispatcher

    order, seen = [], set()

    def visit(f):
        if id(f) in seen:
            return
        seen.add(id(f))
        names = f.py_func.__code__.co_names
        for name in names:
            found = f.py_func.__globals__.get(name)
            if isinstance(found, types.ModuleType):  # module.function
                for callee in (getattr(found, attr, None) for attr in names):
                    if isinstance(callee, CPUDispatcher):
                        visit(callee)
            elif isinstance(found, CPUDispatcher):
                visit(found)
        order.append(f)

    for f in functions:
        visit(f)
    return order


def load_cached_callees_first() -> None:
    """Load every overload of mjrft's compiled functions that numba's cache holds, callees before callers, once
    per process (:func:`loaded_count` says how many).

    Why: numba links a copy of each compiled callee into its caller, and the process resolves the caller's call
    to whichever definition of the callee it loaded first. A process that compiles the kernels compiles (and so
    loads) each callee before its caller and runs the callees' own code; a process that loads a caller from the
    cache before its callee would run the caller's copy, which the optimiser may have compiled with other fused
    multiply-adds, so its physics could differ in the last bits from the compiling process's (and depend on
    which function it called first). Loading callees first makes every process run the same code. Uses numba's
    cache index (a private interface): where it is missing the loading is skipped, and
    tests/mjrft/test_jit_cache.py, which compares processes that call different kernels first, fails."""
    with _loading:  # a second thread building a terrain waits until the loading is done
        if _loaded is None:
            _load_callees_first()


def _load_callees_first() -> None:
    global _loaded
    _loaded = 0
    import importlib

    from numba.core.registry import CPUDispatcher

    roots = []
    for module in compiled_modules():
        roots += [f for f in vars(importlib.import_module(module)).values() if isinstance(f, CPUDispatcher)]
    for f in callees_first(roots):
        cache = getattr(f, "_cache", None)
        try:
            codegen = f.targetctx.codegen()
            keys = list(cache._cache_file._load_index())
        except AttributeError:  # a function without a disk cache, or another numba
            continue
        for key in keys:
            if key == cache._index_key(key[0], codegen):  # this process's target and this source
                f.compile(key[0])
                _loaded += 1


def loaded_count() -> int:
    """How many cached overloads :func:`load_cached_callees_first` loaded in this process (0 before it ran)."""
    return _loaded or 0
