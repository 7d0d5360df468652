"""What the commands write: output paths checked before any work starts, and numbers printed without noise.

``output_dir(path, option)`` creates the folder and proves it can be written; ``output_file(path,
option)`` does the same for the folder a file goes into and refuses a path that is a folder. Both
raise ``ValueError`` naming the option, the path and the reason, so the command line prints one
line (exit status 2) instead of a traceback after the work is done. Nothing is left behind: the
probe file is removed again, the output file itself is not created until it is written, and
:func:`remove_empty_created` (called by the command line when a command fails or is interrupted)
removes the folders these checks created that are still empty.

``number(x, spec, scale)`` formats a printed number: a value below ``NOISE`` x ``scale`` (floating-point
round-off, e.g. the 1e-16 N drag of a plate pushed straight down) and a negative zero such as
``-0.000`` print as zero.

``WarningNotes`` collects the warnings a command raises while it works and prints them after its output
as short notes, one line per kind of warning with its count and first message (``note: 3 terrain
stability warning(s), first: ...``), instead of Python's default lines with the source file and line
of each (``mjrft demo``, ``rollout``, ``eval`` and ``plot`` use it).
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
import warnings

__all__ = ["NOISE", "WarningNotes", "number", "output_dir", "output_file", "remove_empty_created", "warning_kind"]

NOISE = 1e-9  # relative size below which a printed value is round-off


def number(x, spec: str = ".4g", scale: float | None = None) -> str:
    """``format(x, spec)``, with round-off (``|x| < NOISE * scale``, scale defaults to ``|x|``) and ``-0`` as 0."""
    x = float(x)
    if scale is not None and abs(x) < NOISE * abs(scale):
        x = 0.0
    text = format(x, spec)
    if "-" in text.split("e")[0] and not any(c in "123456789" for c in text.split("e")[0]):
        text = format(0.0, spec)  # "-0.000", "  -0.00" -> "0.000", "   0.00"
    return text


#: folders created by output_dir / output_file in this process, outermost first
_CREATED: list[str] = []


def remove_empty_created() -> None:
    """Remove the folders :func:`output_dir` / :func:`output_file` created that are still empty (innermost first)."""
    while _CREATED:
        try:
            os.rmdir(_CREATED.pop())
        except OSError:  # not empty (something was written), or already gone
            pass


def _probe(folder: str, option: str, path: str) -> None:
    missing, parent = [], os.path.abspath(folder)
    while parent and not os.path.exists(parent):
        missing.append(parent)
        parent, prev = os.path.dirname(parent), parent
        if parent == prev:
            break
    try:
        os.makedirs(folder, exist_ok=True)
        _CREATED.extend(reversed(missing))
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


# ---------------------------------------------------------------------------------------------- warnings
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def warning_kind(category: str, message: str) -> str:
    """The kind of a warning: its category and message with every number replaced by ``#`` (the same body's
    stability warning at any time is one kind)."""
    return f"{category}: {_NUMBER.sub('#', message)}"


def _what(category: type) -> str:
    """``TerrainStabilityWarning`` -> ``terrain stability``, ``RuntimeWarning`` -> ``runtime``."""
    name = category.__name__.removesuffix("Warning") or category.__name__
    return " ".join(w.lower() if not w.isupper() else w for w in re.findall(r"[A-Z]+(?![a-z])|[A-Z]?[a-z0-9]+", name))


class WarningNotes:
    """Collects the warnings raised inside ``with WarningNotes() as notes:``; ``notes.lines()`` (or
    ``notes.print()``) gives one note per kind (:func:`warning_kind`) in the order each kind first came,
    ``note: N <category> warning(s), first: <message>``.

    Every warning of ``counted`` (and its subclasses: mjrft's terrain, validity-range, sand-contact and gait
    warnings are ``UserWarning`` / ``RuntimeWarning``) is counted each time it is raised; other categories
    follow the filters in force (Python's defaults hide ``DeprecationWarning`` outside ``__main__``).
    """

    def __init__(self, counted=(UserWarning, RuntimeWarning)):
        self.counted = tuple(counted)
        self.caught: list = []

    def __enter__(self) -> WarningNotes:
        self._context = warnings.catch_warnings(record=True)
        self.caught = self._context.__enter__()
        for category in self.counted:
            warnings.simplefilter("always", category)
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        self._context.__exit__(exc_type, exc, tb)
        if exc_type is not None:  # the command failed: what was noted so far still goes out (on stderr)
            self.print(file=sys.stderr)
        return False

    def lines(self, indent: str = "") -> list[str]:
        kinds: dict[str, list] = {}
        for w in self.caught:
            kinds.setdefault(warning_kind(w.category.__name__, str(w.message)), []).append(w)
        out = []
        for found in kinds.values():
            first = str(found[0].message).removeprefix("mjrft: ")
            out.append(f"{indent}note: {len(found)} {_what(found[0].category)} warning(s), first: {first}")
        return out

    def print(self, indent: str = "", file=None) -> None:
        for line in self.lines(indent):
            print(line, file=file)
