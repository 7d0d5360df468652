"""The README and the user guide (``docs/*.md``) stay true.

* Every ```python block runs, in page order, each page in one namespace (a block may use what an earlier
  block of its page defined), from a temporary folder. A block is skipped only when its first line is
  ``# doc-test: skip (reason)`` with a reason. Wall time is not asserted (tests hold no absolute times: a loaded
  2-core machine takes several times as long); ``make test`` lists the slowest pages (``--durations``).
* Every relative link and image of a page points at a file or folder that exists (anchors are not checked).
* ``docs/cli.md`` is the current ``mjrft --help`` and ``mjrft <command> --help`` text
  (regenerate it with ``python docs/cli_reference.py``).

The terrain kernels are compiled (or loaded from the on-disk cache) once before the blocks run.
"""

from __future__ import annotations

import re
import sys
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```([\w+-]*)[^\n]*\n(.*?)^```[ \t]*$", re.S | re.M)
SKIP = re.compile(r"^#\s*doc-test:\s*skip\s*\((?P<reason>[^)]*\S[^)]*)\)\s*$")
MARKER = re.compile(r"^#\s*doc-test\b")
LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML_SRC = re.compile(r"<(?:img|a)\b[^>]*?\b(?:src|href)=\"([^\"]+)\"", re.I)
INLINE_CODE = re.compile(r"`[^`\n]*`")


def _rel(page: Path) -> str:
    return str(page.relative_to(ROOT))


def code_blocks(page: Path, language: str = "python") -> list[tuple[int, str]]:
    """(first line number, source) of each fenced block of ``language`` in ``page``."""
    text = page.read_text()
    return [(text.count("\n", 0, m.start(2)) + 1, m.group(2)) for m in FENCE.finditer(text) if m.group(1) == language]


def prose(page: Path) -> str:
    """The page without its fenced blocks and inline code (where link syntax is only an example)."""
    return INLINE_CODE.sub("", FENCE.sub("", page.read_text()))


def test_pages_exist():
    names = {p.name for p in PAGES}
    assert "README.md" in names and "index.md" in names, names


@pytest.fixture(scope="module")
def compiled():
    """Import mjrft and its environments and step a sand environment once: compile or load the kernels."""
    import gymnasium
    import numpy as np

    import mjrft  # noqa: F401

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = gymnasium.make("mjrft/HexapodSand-v0")
        env.reset(seed=0)
        env.step(np.zeros(6, np.float32))
        env.close()


#: pages whose examples need an optional extra: the modules they import (skipped where one is missing)
REQUIRES = {"docs/gpu.md": ("jax", "mujoco.mjx", "brax")}


@pytest.mark.parametrize("page", PAGES, ids=_rel)
def test_python_blocks_run(page, compiled, tmp_path, monkeypatch):
    for module in REQUIRES.get(_rel(page), ()):
        pytest.importorskip(module, reason=f"{_rel(page)}'s examples need the optional extra mjrft[mjx]")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "argv", ["doc-example"])
    namespace = {"__name__": "__doc_example__"}
    for line, source in code_blocks(page):
        first = source.splitlines()[0] if source.strip() else ""
        if MARKER.match(first):
            assert SKIP.match(first), f"{_rel(page)}:{line}: write '# doc-test: skip (reason)', got {first!r}"
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the terrain's range and stability notes are not the example's
                exec(compile(source, f"{_rel(page)}:{line}", "exec"), namespace)
        except Exception as exc:
            raise AssertionError(f"{_rel(page)}, python block at line {line} failed: {exc!r}") from exc


@pytest.mark.parametrize("page", PAGES, ids=_rel)
def test_skip_markers_give_a_reason(page):
    for line, source in code_blocks(page):
        first = source.splitlines()[0] if source.strip() else ""
        if MARKER.match(first):
            assert SKIP.match(first), f"{_rel(page)}:{line}: a skipped block needs '# doc-test: skip (reason)'"


def test_skip_marker_rule():
    assert SKIP.match("# doc-test: skip (needs a GPU)")
    assert not SKIP.match("# doc-test: skip")
    assert not SKIP.match("# doc-test: skip ()")
    assert not SKIP.match("# doc-test: skip (  )")


@pytest.mark.parametrize("page", PAGES, ids=_rel)
def test_relative_links_exist(page):
    text = prose(page)
    targets = LINK.findall(text) + HTML_SRC.findall(text)
    missing = []
    for target in targets:
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I) or target.startswith("#"):
            continue  # a URL (http:, mailto:, ...) or an anchor on the same page
        path = target.split("#", 1)[0].split("?", 1)[0]
        if not (page.parent / path).exists():
            missing.append(target)
    assert not missing, f"{_rel(page)}: links to missing files: {missing}"


def test_link_pattern():
    text = "see [a](docs/x.md#y), ![img](img/a.png \"t\"), [b](https://e.org) and [c [d]](e.md)"
    assert LINK.findall(text) == ["docs/x.md#y", "img/a.png", "https://e.org", "e.md"]


def test_cli_reference_is_current():
    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import cli_reference
    finally:
        sys.path.pop(0)
    assert (ROOT / "docs" / "cli.md").read_text() == cli_reference.render(), (
        "docs/cli.md differs from the current 'mjrft ... --help': run 'python docs/cli_reference.py'")
