"""Output paths checked before any work starts: every command that writes files calls these first.

``output_dir(path, option)`` creates the folder and proves it can be written; ``output_file(path,
option)`` does the same for the folder a file goes into and refuses a path that is a folder. Both
raise ``ValueError`` naming the option, the path and the reason, so the command line prints one
line (exit status 2) instead of a traceback after the work is done. Nothing is left behind: the
probe file is removed again, and the output file itself is not created until it is written.
"""

from __future__ import annotations

import os
import tempfile

__all__ = ["output_dir", "output_file"]


def _probe(folder: str, option: str, path: str) -> None:
    try:
        os.makedirs(folder, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".mjrft-write-test-"):
            pass
    except OSError as exc:
        raise ValueError(f"{option} {path!r} cannot be written: {exc.strerror or exc}") from None


def output_dir(path, option: str = "--out") -> str:
    """Create folder ``path`` (with its parents) and check it can be written; returns the path."""
    path = os.fspath(path)
    if os.path.exists(path) and not os.path.isdir(path):
        raise ValueError(f"{option} {path!r} cannot be written: it is a file, not a folder")
    _probe(path, option, path)
    return path


def output_file(path, option: str = "--out") -> str:
    """Check that file ``path`` can be written (its folder is created if missing); returns the path."""
    path = os.fspath(path)
    if os.path.isdir(path):
        raise ValueError(f"{option} {path!r} cannot be written: it is a folder, not a file")
    if os.path.exists(path) and not os.access(path, os.W_OK):
        raise ValueError(f"{option} {path!r} cannot be written: permission denied")
    _probe(os.path.dirname(os.path.abspath(path)), option, path)
    return path
