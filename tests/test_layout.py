"""The package's two layers: the physics core imports no tool, the tools live in mjrft.tools, and each tool's
former path ``mjrft.<tool>`` still imports the same module (with a DeprecationWarning naming the new path)."""

import ast
import importlib
import pathlib
import pickle
import subprocess
import sys
import tomllib

import pytest

import mjrft
import mjrft.tools

PKG = pathlib.Path(mjrft.__file__).parent
REPO = PKG.parent
TOOLS = mjrft.tools.__all__


def module_name(path: pathlib.Path) -> str:
    parts = list(path.relative_to(PKG.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(text: str, name: str, is_package: bool = False) -> set[str]:
    """Absolute names of every module the source ``text`` of module ``name`` imports, anywhere in it (``from x
    import y`` counts x and x.y)."""
    package = name if is_package else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            out.add(base)
            out.update(f"{base}.{a.name}" for a in node.names)
    return out


def file_imports(path: pathlib.Path) -> set[str]:
    return imported_modules(path.read_text(), module_name(path), path.name == "__init__.py")


def is_tool(module: str) -> bool:
    parts = module.split(".")
    return parts[0] == "mjrft" and len(parts) > 1 and (parts[1] in TOOLS or (parts[1] == "tools" and len(parts) > 2))


CORE_FILES = sorted(p for p in PKG.rglob("*.py") if "tools" not in p.relative_to(PKG).parts)


def test_core_files_are_found():
    names = {module_name(p) for p in CORE_FILES}
    assert {"mjrft.coupler", "mjrft.kernel", "mjrft.batch", "mjrft.media", "mjrft.errors", "mjrft.laws.rft",
            "mjrft.geometry.discretize"} <= names
    assert not any(n.startswith("mjrft.tools") for n in names)


@pytest.mark.parametrize("path", CORE_FILES, ids=lambda p: str(p.relative_to(PKG)))
def test_core_imports_no_tool(path):
    tools = sorted(m for m in file_imports(path) if is_tool(m))
    assert not tools, f"{path.relative_to(REPO)} imports tool module(s) {tools}; the core must not depend on mjrft.tools"


def test_the_check_sees_tool_imports():
    src = ("from ..tools import gaits\nfrom .. import rigs\nimport mjrft.presets\n"
           "def f():\n    from mjrft.tools.validation import case\n")
    found = sorted(m for m in imported_modules(src, "mjrft.laws.probe") if is_tool(m))
    assert found == ["mjrft.presets", "mjrft.rigs", "mjrft.tools.gaits", "mjrft.tools.validation",
                     "mjrft.tools.validation.case"]
    core = "from ..media import Medium\nfrom . import registry\nimport mjrft.models.rigs\nfrom .. import tools\n"
    assert not [m for m in imported_modules(core, "mjrft.laws.probe") if is_tool(m)]


def test_tools_all_lists_every_tool_and_the_docstring_names_them():
    on_disk = {p.stem for p in (PKG / "tools").glob("*.py") if p.stem != "__init__"}
    on_disk |= {p.name for p in (PKG / "tools").iterdir() if (p / "__init__.py").exists()}
    assert set(TOOLS) == on_disk
    for name in TOOLS:
        assert f"``{name}``" in mjrft.tools.__doc__, name


def test_top_level_holds_no_tool():
    top = {p.stem for p in PKG.glob("*.py")} | {p.name for p in PKG.iterdir() if (p / "__init__.py").exists()}
    assert "tools" in top
    assert not top & set(TOOLS), f"tool modules at the top level of mjrft/: {sorted(top & set(TOOLS))}"


def test_public_names_import():
    for name in mjrft.__all__:
        assert getattr(mjrft, name) is not None, name
    from mjrft import GranularTerrain, MEDIA, Region, calibrate, laws, models, tools  # noqa: F401


@pytest.mark.parametrize("tool", TOOLS)
def test_former_path_is_the_same_module_with_a_warning(tool, monkeypatch):
    new = importlib.import_module(f"mjrft.tools.{tool}")
    monkeypatch.delitem(sys.modules, f"mjrft.{tool}", raising=False)  # as if first imported now
    monkeypatch.delattr(mjrft, tool, raising=False)
    with pytest.warns(DeprecationWarning, match=rf"mjrft\.{tool} is now mjrft\.tools\.{tool}"):
        old = importlib.import_module(f"mjrft.{tool}")
    assert old is new
    assert old.__name__ == old.__spec__.name == f"mjrft.tools.{tool}"  # the module keeps its own identity
    assert getattr(mjrft, tool) is new


def test_former_paths_of_submodules_and_from_imports(monkeypatch):
    for name in ("mjrft.validation", "mjrft.validation.cases", "mjrft.validation.cases.li2013", "mjrft.gaits"):
        monkeypatch.delitem(sys.modules, name, raising=False)
    monkeypatch.delattr(mjrft, "gaits", raising=False)
    with pytest.warns(DeprecationWarning) as record:
        import mjrft.validation.cases.li2013 as old
    import mjrft.tools.validation.cases.li2013 as new
    assert old is new
    assert {str(w.message).split()[0] for w in record} == {"mjrft.validation", "mjrft.validation.cases",
                                                           "mjrft.validation.cases.li2013"}
    with pytest.warns(DeprecationWarning, match="mjrft.tools.gaits"):
        from mjrft import gaits
        from mjrft.gaits import make_gait
    assert gaits is mjrft.tools.gaits and make_gait is mjrft.tools.gaits.make_gait


def test_pickles_naming_a_former_path_load():
    import mjrft.tools.gaits as gaits
    assert pickle.loads(b"cmjrft.gaits\nmake_gait\n.") is gaits.make_gait  # protocol 0: module path as text
    assert b"mjrft.tools.gaits" in pickle.dumps(gaits.make_gait)


@pytest.mark.parametrize("module", ["mjrft.tools.cli", "mjrft.cli"])
def test_python_dash_m_runs_the_cli(module, tmp_path):
    out = subprocess.run([sys.executable, "-W", "default::DeprecationWarning", "-m", module, "--help"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.startswith("usage: mjrft"), out.stdout[:200]
    assert ("mjrft.cli is now mjrft.tools.cli" in out.stderr) == (module == "mjrft.cli"), out.stderr[-2000:]


def test_console_script_and_packages_in_pyproject():
    meta = tomllib.loads((REPO / "pyproject.toml").read_text())
    entry = meta["project"]["scripts"]["mjrft"]
    assert entry == "mjrft.tools.cli:main"
    mod, func = entry.split(":")
    assert callable(getattr(importlib.import_module(mod), func))
    packages = set(meta["tool"]["setuptools"]["packages"])
    on_disk = {module_name(p) for p in PKG.rglob("__init__.py")}
    assert on_disk <= packages, f"packages missing from pyproject.toml: {sorted(on_disk - packages)}"
    assert "data/*.json" in meta["tool"]["setuptools"]["package-data"]["mjrft.tools.validation"]
