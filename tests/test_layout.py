"""The package's layers: the physics core (every module of mjrft/ outside mjrft/tools/, its ``__init__``
included) imports nothing from mjrft.tools, mjrft.envs or mjrft.train, and the tools live in mjrft.tools. No test
module imports another."""

import ast
import importlib
import importlib.util
import pathlib
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


ABOVE = ("tools", "envs", "train")
#: the one import of a layer above the core: mjrft/__init__.py imports mjrft.envs, when gymnasium is installed, so
#: that ``import mjrft`` registers the gymnasium ids
ALLOWED = {"__init__.py": {"mjrft.envs"},
           # mjrft.mjx.envs re-exports the registry of MJX environments (mjrft.envs.mjx), as Playground's registry
           # sits next to its environments; mjrft.mjx itself does not import it
           "mjx/envs.py": {"mjrft.envs.mjx"}}


def is_above(module: str) -> bool:
    """Whether ``module`` is in one of the layers above the core (mjrft.tools, mjrft.envs, mjrft.train)."""
    parts = module.split(".")
    return parts[0] == "mjrft" and len(parts) > 1 and parts[1] in ABOVE


CORE_FILES = sorted(p for p in PKG.rglob("*.py") if "tools" not in p.relative_to(PKG).parts)


def test_core_files_are_found():
    names = {module_name(p) for p in CORE_FILES}
    assert {"mjrft", "mjrft._jit_cache", "mjrft.coupler", "mjrft.kernel", "mjrft.batch", "mjrft.media", "mjrft.errors",
            "mjrft.laws.rft", "mjrft.geometry.discretize"} <= names
    assert not any(n.startswith("mjrft.tools") for n in names)


@pytest.mark.parametrize("path", CORE_FILES, ids=lambda p: str(p.relative_to(PKG)))
def test_core_imports_nothing_above_it(path):
    allowed = ALLOWED.get(str(path.relative_to(PKG)), set())
    above = sorted(m for m in file_imports(path) if is_above(m) and m not in allowed)
    assert not above, (f"{path.relative_to(REPO)} imports {above}; the core must not depend on mjrft.tools, "
                       "mjrft.envs or mjrft.train")


def test_the_check_sees_imports_from_above():
    src = ("from ..tools import gaits\nfrom .. import envs\nimport mjrft.train.evaluate\n"
           "def f():\n    from mjrft.tools.validation import case\n")
    found = sorted(m for m in imported_modules(src, "mjrft.laws.probe") if is_above(m))
    assert found == ["mjrft.envs", "mjrft.tools", "mjrft.tools.gaits", "mjrft.tools.validation",
                     "mjrft.tools.validation.case", "mjrft.train.evaluate"]
    assert [m for m in imported_modules("from . import tools\n", "mjrft", is_package=True) if is_above(m)] == [
        "mjrft.tools"]
    core = "from ..media import Medium\nfrom . import registry\nimport mjrft.models.rigs\nfrom .. import kernel\n"
    assert not [m for m in imported_modules(core, "mjrft.laws.probe") if is_above(m)]


def test_import_mjrft_loads_no_tool_and_no_training_code(tmp_path):
    code = ("import sys, mjrft\n"
            "print(sorted(m for m in sys.modules if m.split('.')[:2] in (['mjrft', 'tools'], ['mjrft', 'train'])))\n"
            "print(mjrft.tools.__name__, 'mjrft.tools' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.splitlines() == ["[]", "mjrft.tools True"]  # mjrft.tools: imported on first access


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


def test_tools_have_only_their_path_under_mjrft_tools():
    for tool in TOOLS:
        assert importlib.util.find_spec(f"mjrft.{tool}") is None, tool


def test_python_dash_m_runs_the_cli(tmp_path):
    out = subprocess.run([sys.executable, "-m", "mjrft.tools.cli", "--help"], cwd=tmp_path, capture_output=True,
                         text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.startswith("usage: mjrft"), out.stdout[:200]


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


def test_no_test_module_imports_another():
    for path in sorted((REPO / "tests").rglob("test_*.py")):
        found = sorted(m for m in imported_modules(path.read_text(), path.stem)
                       if m.split(".")[0].startswith("test_") or m.split(".")[0] in ("conftest", "tests"))
        assert not found, (f"{path.relative_to(REPO)} imports {found}: shared fixtures go in tests/conftest.py, shared "
                           "helpers in tests/helpers.py")


def test_test_modules_have_unique_names():
    """pytest imports the test modules by their file name (the test folders are not packages), so two files of the
    same name in different folders would clash."""
    seen = {}
    for path in sorted((REPO / "tests").rglob("test_*.py")):
        assert path.name not in seen, f"{path.relative_to(REPO)} and {seen[path.name].relative_to(REPO)}"
        seen[path.name] = path


def test_train_modules_import_each_other_in_one_direction():
    """No import cycle among the modules of mjrft.train, imports inside functions included: shared helpers live
    in mjrft.train.common."""
    train_dir = REPO / "train"
    graph = {}
    for path in train_dir.glob("*.py"):
        deps = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module:
                deps.add(node.module.split(".")[0])
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("mjrft.train."):
                deps.add(node.module.split(".")[2])
        graph[path.stem] = deps

    def cycle_from(start):
        stack = [(start, [start])]
        while stack:
            node, trail = stack.pop()
            for dep in graph.get(node, ()):
                if dep == start:
                    return trail + [dep]
                if dep not in trail:
                    stack.append((dep, trail + [dep]))
        return None

    cycles = [c for c in map(cycle_from, graph) if c]
    assert not cycles, f"import cycles in mjrft.train: {cycles}"
    assert graph["common"] <= {"run_warnings"}  # the shared helpers depend on (almost) nothing
