"""Finding MuJoCo's C library (mjrft.mujoco_c): each platform's file names next to the mujoco package, and the
real library of this installation."""

from __future__ import annotations

import ctypes
import os
import sys

import mujoco
import pytest

from mjrft import mujoco_c

#: what a mujoco wheel's package folder holds on each platform (the library, its bindings, decoys of the others)
FOLDERS = {
    "linux": ["__init__.py", "_functions.cpython-311-x86_64-linux-gnu.so", "libmujoco.so.3.3.0",
              "_structs.cpython-311-x86_64-linux-gnu.so", "plugin"],
    "darwin": ["__init__.py", "_functions.cpython-311-darwin.so", "libmujoco.3.3.0.dylib", "plugin"],
    "win32": ["__init__.py", "_functions.cp311-win_amd64.pyd", "mujoco.dll", "plugin"],
}
EXPECTED = {"linux": "libmujoco.so.3.3.0", "darwin": "libmujoco.3.3.0.dylib", "win32": "mujoco.dll"}


def fake_folder(tmp_path, names):
    for n in names:
        (tmp_path / n).write_bytes(b"")
    return str(tmp_path)


@pytest.mark.parametrize("platform", sorted(FOLDERS))
def test_each_platforms_library_is_found_by_its_name(tmp_path, monkeypatch, platform):
    monkeypatch.setattr(sys, "platform", platform)
    folder = fake_folder(tmp_path, FOLDERS[platform])
    assert mujoco_c.find_library(folder) == os.path.join(folder, EXPECTED[platform])


@pytest.mark.parametrize("platform", sorted(FOLDERS))
def test_another_platforms_library_is_not_taken(tmp_path, monkeypatch, platform):
    monkeypatch.setattr(sys, "platform", platform)
    others = [EXPECTED[p] for p in EXPECTED if p != platform]
    assert mujoco_c.find_library(fake_folder(tmp_path, ["__init__.py", *others])) is None


def test_platform_names():
    assert [mujoco_c.platform_key(p) for p in ("linux", "darwin", "win32", "cygwin", "freebsd14")] == [
        "linux", "darwin", "windows", "windows", "linux"]


def test_unversioned_and_several_versions(tmp_path, monkeypatch):
    (tmp_path / "mac").mkdir()
    (tmp_path / "linux").mkdir()
    monkeypatch.setattr(sys, "platform", "darwin")
    folder = fake_folder(tmp_path / "mac", ["libmujoco.dylib"])
    assert mujoco_c.find_library(folder) == os.path.join(folder, "libmujoco.dylib")
    monkeypatch.setattr(sys, "platform", "linux")
    folder = fake_folder(tmp_path / "linux", ["libmujoco.so", "libmujoco.so.3", "libmujoco.so.3.3.0"])
    assert mujoco_c.find_library(folder) == os.path.join(folder, "libmujoco.so.3")  # versioned first, sorted
    assert mujoco_c.find_library(str(tmp_path / "missing")) is None


def test_the_installed_library_is_the_one_the_bindings_use():
    path = mujoco_c.find_library()
    assert path is not None and os.path.isfile(path)
    assert os.path.dirname(path) == os.path.dirname(mujoco.__file__) or "mujoco" in os.path.basename(path)
    lib = ctypes.CDLL(path)
    lib.mj_version.restype = ctypes.c_int
    assert lib.mj_version() == mujoco.mj_version()
    step = mujoco_c.mujoco_step_functions()
    assert step is not None and all(isinstance(a, int) and a > 0 for a in step)
    assert mujoco_c.mujoco_functions("mj_step1", "no_such_function") is None


def test_no_library_means_no_functions(monkeypatch):
    monkeypatch.setattr(mujoco_c, "find_library", lambda *a, **k: None)
    assert mujoco_c.mujoco_functions("mj_step1") is None
