"""The package's layers: the physics core (every module of mjrft/ outside mjrft/tools/, its ``__init__``
included) imports nothing from mjrft.tools, mjrft.envs or mjrft.train, and the tools live in mjrft.tools. No test
module imports another."""

import ast
import importlib
import importlib.util
import pathlib
import re
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
ALLOWED = {"__init__.py": {"mjrft.envs"}}


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


# ------------------------------------------------------------------------------------------------
# self-contained: nothing points outside the repository, and the paths it names exist
# ------------------------------------------------------------------------------------------------
TEXT_SUFFIXES = (".py", ".md", ".json", ".yaml", ".toml", ".txt", ".csv", ".xml", ".cfg")
#: what a user of the package does not have: the development machines' folders and their copies of the papers
#: (written in pieces so that this file does not match itself)
OUTSIDE = re.compile("|".join(["granular" + "-physics", "shared/" + "seeds", "shared/" + "reference", r"\.\./" + "shared",
                               "/" + "work/"]))
#: a path the repository names (the installed mjrft.envs, mjrft.train and mjrft.models live in envs/, train/, models/)
PATH_MENTION = re.compile(r"(?<![\w/.-])((?:mjrft|envs|train|models|benchmarks|docs|tests)/[\w/.-]*\w\.(?:py|md|json|yaml))\b")
THIS_FILE = pathlib.Path(__file__).resolve()
INSTALLED_AS = {"mjrft/envs/": "envs/", "mjrft/train/": "train/", "mjrft/models/": "models/"}
#: paths named on purpose although they do not exist: (file, path) -> why
MADE_UP_PATHS = {("tests/test_docs.py", "docs/x.md"): "the link pattern's example text"}


def repository_text_files() -> list[pathlib.Path]:
    """The repository's tracked text files (every file under its folders when git is not at hand)."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, capture_output=True, text=True, timeout=60, check=True)
        names = [n for n in out.stdout.split("\0") if n]
    except (OSError, subprocess.SubprocessError):
        names = [str(p.relative_to(REPO)) for p in REPO.rglob("*") if p.is_file()
                 and not {".git", ".venv", "__pycache__"} & set(p.relative_to(REPO).parts)]
    return [REPO / n for n in sorted(names) if n.endswith(TEXT_SUFFIXES) or n == "Makefile"]


def outside_references(text: str, captured_output: bool = False) -> list[str]:
    """The references to files outside the repository in ``text``. ``captured_output``: a committed result, whose
    captured warnings may name the folder its command ran in; only references to the papers' copies count there."""
    return [m.group(0) for m in OUTSIDE.finditer(text) if not (captured_output and m.group(0) == "/" + "work/")]


def test_nothing_refers_to_files_outside_the_repository():
    found = []
    for path in repository_text_files():
        rel = path.relative_to(REPO)
        captured = rel.parts[:2] == ("benchmarks", "results")
        for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            if outside_references(line, captured):
                found.append(f"{rel}:{n}: {line.strip()[:120]}")
    assert not found, ("references to files outside the repository (cite the paper instead: authors, title, "
                       "figure/table):\n" + "\n".join(found))


def test_the_outside_check_sees_each_kind():
    for text in ("see granular" + "-physics.md sec. 1", "/" + "work/shared/" + "seeds/003_*", "../" + "shared/x",
                 "shared/" + "reference/y"):
        assert outside_references(text), text
    assert outside_references("/" + "work/main/envs/base.py:240: Warning") and not outside_references(
        "/" + "work/main/envs/base.py:240: Warning", captured_output=True)
    assert not outside_references("Li, Zhang & Goldman, Science 2013, suppl. table S2")


def stale_paths(text: str, where: str) -> list[str]:
    out = []
    for p in PATH_MENTION.findall(text):
        on_disk = p
        for installed, folder in INSTALLED_AS.items():
            if p.startswith(installed):
                on_disk = folder + p[len(installed):]
        if not (REPO / on_disk).exists() and (where, p) not in MADE_UP_PATHS:
            out.append(p)
    return out


def test_named_paths_exist():
    """Every path of a repository file that code, docs, tests and benchmark scripts name exists (a renamed module
    leaves no stale name behind); committed results are what their commands printed, and are not checked."""
    found = []
    for path in repository_text_files():
        rel = path.relative_to(REPO)
        if rel.parts[:2] == ("benchmarks", "results") or rel.suffix in (".csv", ".xml") or path == THIS_FILE:
            continue  # THIS_FILE plants stale paths to test the check
        for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            found += [f"{rel}:{n}: {p}" for p in stale_paths(line, str(rel))]
    assert not found, "paths that do not exist:\n" + "\n".join(found)


def test_the_path_check_sees_a_stale_path():
    assert stale_paths("see ``mjrft/tradeoff.py`` and mjrft/tools/presets.py", "x.py") == ["mjrft/tradeoff.py"]
    assert stale_paths("mjrft/envs/base.py, mjrft/validation/data/li2013.json", "x.py") == [
        "mjrft/validation/data/li2013.json"]
    assert not stale_paths("[a](docs/x.md#y)", "tests/test_docs.py")
