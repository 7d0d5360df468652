"""Installing mjrft as a new user does: ``pip install -e .`` without setuptools' warnings about data folders."""

from __future__ import annotations

import glob
import itertools
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _package_dir(package: str, dirs: dict) -> Path:
    top = max((p for p in dirs if package == p or package.startswith(p + ".")), key=len)
    return ROOT / dirs[top] / Path(*package[len(top):].split(".")[1:])


def test_every_folder_of_package_data_is_a_listed_package():
    """setuptools warns "Package 'X' is absent from the `packages` configuration" for each folder that holds package
    data and that Python could import as a package (the leading folders with identifier names, below the nearest
    listed package): the same check here."""
    tool = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages, dirs = set(tool["packages"]), tool["package-dir"]
    where = {_package_dir(p, dirs): p for p in packages}
    files = [Path(f) for package, patterns in tool["package-data"].items() for pattern in patterns
             for f in glob.glob(str(_package_dir(package, dirs) / pattern))]
    assert len(files) > 10, "hardly any package data found: the check itself is broken"
    unlisted = set()
    for file in files:
        home = max((d for d in where if d in file.parents), key=lambda d: len(d.parts))
        parts = list(itertools.takewhile(str.isidentifier, file.parent.relative_to(home).parts))
        if parts:
            unlisted.add(".".join((where[home], *parts)))
    assert not unlisted, f"folders of package data missing from pyproject.toml's packages: {sorted(unlisted)}"
