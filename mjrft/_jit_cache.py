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
from pathlib import Path

import numba


def configure() -> str:
    root = Path(__file__).resolve().parent
    h = hashlib.sha1(numba.__version__.encode())
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        if b"numba" in text or path.relative_to(root).as_posix() in ("media.py", "laws/registry.py"):
            h.update(str(path.relative_to(root)).encode())
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
