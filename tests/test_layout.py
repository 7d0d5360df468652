"""The package's layers, each importing only from itself and the layers before it:

    core (mjrft/ outside mjrft/tools/, its ``__init__`` included)  <-  models (models/, installed as mjrft.models)
    <-  tools (mjrft/tools/)  <-  envs (envs/, mjrft.envs)  <-  train (train/, mjrft.train)

so the models depend on nothing above the core. Imports inside functions count, and so do the literal module
names given to ``importlib.import_module`` and the gymnasium ids of mjrft's environments given to ``make`` (an
import of mjrft.envs). The exceptions are listed, each with its reason, in :data:`ALLOWED`. The tools live in
mjrft.tools; no test module imports another; nothing refers to files outside the repository."""

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
#: package -> its folder (pyproject.toml's package-dir: envs/ is installed as mjrft.envs, ...)
PACKAGE_DIRS = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]["package-dir"]

#: the layers, lowest first: a module may import from its own layer and the layers before it
LAYERS = ("core", "models", "tools", "envs", "train")
#: the first two parts of a module's name -> its layer (any other mjrft.* module is in the core)
LAYER_OF_PACKAGE = {"mjrft.models": "models", "mjrft.tools": "tools", "mjrft.envs": "envs", "mjrft.train": "train"}
_ROBOT_CASE = ("a robot experiment of the paper, run on the gymnasium environment as users make it (the case "
               "validates the env and its gait); without it the case needs the robot's action mapping and settings "
               "below mjrft.tools (issue 38's one task definition per robot) or its own copy of the env")
#: the imports against the layers, each with its reason: file (relative to the repository) -> {module: reason}; a
#: module allows its submodules and names too. Documented re-exports (e.g. one package of a lower layer giving
#: access to one of a higher layer) belong here.
ALLOWED: dict[str, dict[str, str]] = {
    "mjrft/__init__.py": {
        "mjrft.envs": "when gymnasium is installed, import mjrft registers the environments' gymnasium ids",
        "mjrft.models": "mjrft.models is an attribute of mjrft after import mjrft (the README's first example)",
    },
    "mjrft/mjx/envs.py": {
        "mjrft.envs.mjx": "the registry of MJX environments, where Playground's users look for it (mjrft.mjx.envs), "
                          "re-exports the environments of the env layer (mjrft.envs.mjx), imported when asked",
    },
    "mjrft/tools/validation/cases/li2013_robot.py": {"mjrft.envs": _ROBOT_CASE},
    "mjrft/tools/validation/cases/thesis_biped.py": {"mjrft.envs.biped": _ROBOT_CASE},
    "mjrft/tools/validation/cases/thesis_hubo.py": {"mjrft.envs.humanoid": _ROBOT_CASE},
}
#: a gymnasium id of one of mjrft's environments
GYM_ID = re.compile(r"^mjrft/\w+-v\d+$")


def module_name(path: pathlib.Path) -> str:
    """The installed name of the module at ``path`` (``envs/base.py`` -> ``mjrft.envs.base``)."""
    path = path.resolve()
    package, folder = max(((pkg, (REPO / d).resolve()) for pkg, d in PACKAGE_DIRS.items()
                           if path.is_relative_to((REPO / d).resolve())), key=lambda pd: len(pd[1].parts))
    parts = [package, *path.relative_to(folder).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(text: str, name: str, is_package: bool = False) -> set[str]:
    """Absolute names of every module the source ``text`` of module ``name`` imports, anywhere in it (``from x
    import y`` counts x and x.y), with the literal names given to ``import_module`` / ``__import__`` and
    ``mjrft.envs`` for each literal gymnasium id of mjrft's given to ``make``."""
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
        elif isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant) \
                and isinstance(node.args[0].value, str):
            func = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
            if func in ("import_module", "__import__"):
                out.add(node.args[0].value)
            elif func == "make" and GYM_ID.match(node.args[0].value):
                out.add("mjrft.envs")
    return out


def file_imports(path: pathlib.Path) -> set[str]:
    return imported_modules(path.read_text(), module_name(path), path.name == "__init__.py")


def layer(module: str) -> str | None:
    """The layer of an mjrft module (None for any other module)."""
    parts = module.split(".")
    if parts[0] != "mjrft":
        return None
    return LAYER_OF_PACKAGE.get(".".join(parts[:2]), "core")


def against_layers(module: str, imports, allowed: dict | None = None) -> list[str]:
    """The names among ``imports`` (of ``module``) in a layer after ``module``'s own, less those ``allowed``."""
    rank = LAYERS.index(layer(module))
    allowed = allowed or {}
    return sorted(m for m in imports if layer(m) is not None and LAYERS.index(layer(m)) > rank
                  and not any(m == a or m.startswith(a + ".") for a in allowed))


LAYER_FILES = sorted(p for d in PACKAGE_DIRS.values() for p in (REPO / d).rglob("*.py"))


def test_every_layer_is_found():
    names = {module_name(p) for p in LAYER_FILES}
    assert {"mjrft", "mjrft._jit_cache", "mjrft.coupler", "mjrft.kernel", "mjrft.batch", "mjrft.media", "mjrft.errors",
            "mjrft.laws.rft", "mjrft.geometry.discretize", "mjrft.models.hexapod", "mjrft.tools.gaits",
            "mjrft.tools.validation.cases.li2013_robot", "mjrft.envs.base", "mjrft.train.train"} <= names
    assert {layer(n) for n in names} == set(LAYERS)
    assert module_name(REPO / "envs" / "__init__.py") == "mjrft.envs"
    assert layer("mjrft") == layer("mjrft.mjx.terrain") == "core" and layer("mjrft.tools") == "tools"


@pytest.mark.parametrize("path", LAYER_FILES, ids=lambda p: str(p.relative_to(REPO)))
def test_imports_follow_the_layers(path):
    rel = str(path.relative_to(REPO))
    name = module_name(path)
    found = against_layers(name, file_imports(path), ALLOWED.get(rel))
    assert not found, (f"{rel} ({layer(name)}) imports {found}; the layers are {' <- '.join(LAYERS)}: a module "
                       "imports only from its own layer and those before it (move what both need to the lower one)")


def test_every_allowed_import_is_there_and_has_its_reason():
    for rel, entries in ALLOWED.items():
        path = REPO / rel
        assert path.is_file(), rel
        used = file_imports(path)
        for module, reason in entries.items():
            assert len(reason) > 20, (rel, module)
            assert any(m == module or m.startswith(module + ".") for m in used), f"{rel} no longer imports {module}"


@pytest.mark.parametrize("module, source, above", [
    ("mjrft.laws.probe", "from ..tools import gaits\nfrom .. import envs\nimport mjrft.train.evaluate\n"
                         "def f():\n    from mjrft.tools.validation import case\n",
     ["mjrft.envs", "mjrft.tools", "mjrft.tools.gaits", "mjrft.tools.validation", "mjrft.tools.validation.case",
      "mjrft.train.evaluate"]),
    ("mjrft.laws.probe", "def f():\n    from mjrft.models.hexapod import hexapod_xml\n",
     ["mjrft.models.hexapod", "mjrft.models.hexapod.hexapod_xml"]),
    ("mjrft.models.probe", "def ik():\n    from mjrft.tools.gaits import humanoid_leg_ik\n",
     ["mjrft.tools.gaits", "mjrft.tools.gaits.humanoid_leg_ik"]),
    ("mjrft.models.probe", "from .. import envs\n", ["mjrft.envs"]),
    ("mjrft.tools.validation.cases.probe", "from mjrft.envs.hexapod import SAND_TIMESTEP\n",
     ["mjrft.envs.hexapod", "mjrft.envs.hexapod.SAND_TIMESTEP"]),
    ("mjrft.tools.probe", "import gymnasium\ndef run():\n    return gymnasium.make('mjrft/HexapodSand-v0')\n",
     ["mjrft.envs"]),
    ("mjrft.tools.probe", "def main(a):\n    from mjrft.train.rollout import rollout\n",
     ["mjrft.train.rollout", "mjrft.train.rollout.rollout"]),
    ("mjrft.tools.probe", "import importlib\nm = importlib.import_module('mjrft.envs.biped')\n", ["mjrft.envs.biped"]),
    ("mjrft.envs.probe", "def f():\n    from ..train import common\n", ["mjrft.train", "mjrft.train.common"]),
], ids=["core imports tools, envs, train", "core imports models in a function", "models import tools in a function",
        "models import envs", "tools import envs", "tools make an env by its gymnasium id", "tools import train",
        "tools import_module an env", "envs import train in a function"])
def test_the_check_sees_an_import_against_the_layers(module, source, above):
    assert against_layers(module, imported_modules(source, module)) == above


def test_the_check_lets_imports_down_the_layers_pass():
    ok = {"mjrft.laws.probe": "from ..media import Medium\nfrom . import registry\nfrom .. import kernel\n",
          "mjrft.models.probe": "from mjrft.geometry import discretize_geom\nfrom .scene import fmt\n",
          "mjrft.tools.probe": "from mjrft.models.biped import biped_leg_ik\nfrom . import presets\n"
                              "import gymnasium\ngymnasium.make('Hopper-v5')\n",
          "mjrft.envs.probe": "from mjrft.tools.presets import resolve\nfrom .base import G\n",
          "mjrft.train.probe": "from mjrft.envs import wrapper\nfrom mjrft.tools.gaits import make_gait\n"}
    for module, source in ok.items():
        assert not against_layers(module, imported_modules(source, module)), module
    assert against_layers("mjrft", imported_modules("from . import envs\n", "mjrft", is_package=True)) == [
        "mjrft.envs"]
    assert not against_layers("mjrft", imported_modules("from . import envs\n", "mjrft", is_package=True),
                              ALLOWED["mjrft/__init__.py"])


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
