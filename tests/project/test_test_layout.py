"""The suite's layout: test modules sit in folders by concern, mirroring the package (soadyn/io/ is tested
in tests/io/, soadyn/campaign/ in tests/campaign/, the core in dynamics/, flex/, loops/, sim/, batch/), and
stand alone: no Python file under tests/ imports a test module (a file named test_*.py). What tests share
lives in support/ (builders, oracle mappings, fixtures) or beside the fuzz cases in fuzz/, so that running,
moving or deleting one test file touches no other."""
from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
PACKAGE = TESTS.parent / "python" / "soadyn"
# folder -> what it tests; a test module anywhere else fails test_test_modules_sit_in_the_concern_folders
CONCERNS = {
    "dynamics": "the model, joint types and the dynamics calls of the core, against oracles",
    "flex": "flexible bodies",
    "loops": "closed loops: closure, constrained dynamics, loop scenes",
    "analysis": "soadyn.analysis: derivatives, linearization, modes, statics, sensitivities",
    "sim": "the Simulator: integrators, sources, events, threads",
    "batch": "soadyn.batch: batched calls and rollouts",
    "fmu": "soadyn.fmu: FMUs exported, validated and run by fmpy and libcosim; the C API",
    "io": "soadyn.io: URDF, MJCF, model files and export",
    "check": "soadyn.check: the oracle adapters and `soadyn check`",
    "viz": "soadyn.viz: the viewer",
    "hil": "soadyn.hil: the HIL runner and its link",
    "apps": "soadyn.apps: the command line, the demo and the scenes",
    "campaign": "soadyn.campaign: campaign specs and runs",
    "fuzz": "the fuzz tests, beside their case generators",
    "project": "the repository, the package, the version and this layout",
}
SHARED = {"support", "fuzz"}  # the packages of helpers the tests import (tests/conftest.py)
NOT_PYTEST = {"cpp"}  # the C++ tests, run by CTest (their Python helpers are CTest's too)


def names_a_test_module(dotted: str) -> bool:
    return any(part.startswith("test_") for part in dotted.split("."))


def imports_of_test_modules(path: Path, root: Path) -> list[str]:
    """'file:line: import statement' for each import in `path` that names a test module, whether as the
    module imported (`import test_x as y`, `from test_x import f`, `from pkg.test_x import f`) or as a
    name taken from a package (`from pkg import test_x`), at module level or inside a function."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            names = [node.module or ""] + [alias.name for alias in node.names]
        else:
            continue
        if any(names_a_test_module(name) for name in names):
            found.append(f"{path.relative_to(root)}:{node.lineno}: {ast.unparse(node)}")
    return found


def python_files() -> list[Path]:
    return sorted(path for path in TESTS.rglob("*.py") if path.relative_to(TESTS).parts[0] not in NOT_PYTEST)


def test_no_test_module_imports_another_test_module():
    sources = python_files()
    assert {TESTS / "conftest.py", TESTS / "support" / "forked.py", TESTS / "dynamics" / "test_model.py",
            TESTS / "fuzz" / "test_regressions.py"} <= set(sources)
    offenders = [line for path in sources for line in imports_of_test_modules(path, TESTS)]
    assert not offenders, "test modules imported as libraries:\n" + "\n".join(offenders)


def test_every_form_of_importing_a_test_module_is_named(tmp_path):
    importer = tmp_path / "test_importer.py"
    importer.write_text("import trees, support.forked\n"
                        "import test_loops\n"
                        "import test_pinocchio_oracle as pinocchio_trees\n"
                        "from support import pinocchio_trees\n"
                        "from test_urdf import joint as any_joint, link\n"
                        "from fuzz.test_regressions import run_forked\n"
                        "from fuzz import test_regressions\n"
                        "from . import test_simulator\n"
                        "from support.four_bar import four_bar\n"
                        "def helper():\n"
                        "    from test_flexible_body import BETA_L\n")
    assert imports_of_test_modules(importer, tmp_path) == [
        "test_importer.py:2: import test_loops",
        "test_importer.py:3: import test_pinocchio_oracle as pinocchio_trees",
        "test_importer.py:5: from test_urdf import joint as any_joint, link",
        "test_importer.py:6: from fuzz.test_regressions import run_forked",
        "test_importer.py:7: from fuzz import test_regressions",
        "test_importer.py:8: from . import test_simulator",
        "test_importer.py:11: from test_flexible_body import BETA_L",
    ]


def test_test_modules_sit_in_the_concern_folders():
    misplaced = [str(path.relative_to(TESTS)) for path in python_files() if path.name.startswith("test_")
                 and (len(path.relative_to(TESTS).parts) != 2 or path.parent.name not in CONCERNS)]
    assert not misplaced, f"test modules outside the folders {sorted(CONCERNS)}: {misplaced}"
    assert all(any((TESTS / folder).glob("test_*.py")) for folder in CONCERNS), "a concern folder without tests"


def test_shared_code_lives_in_support_or_fuzz():
    """A helper module beside the test modules would be a library hidden among them: helpers go to support/
    (or fuzz/, beside the cases they help), the one conftest.py stays at the top."""
    stray = [str(path.relative_to(TESTS)) for path in python_files() if not path.name.startswith("test_")
             and path != TESTS / "conftest.py" and path.relative_to(TESTS).parts[0] not in SHARED]
    assert not stray, f"helper modules outside {sorted(SHARED)}: {stray}"
    assert not list(TESTS.glob("*/conftest.py")), "one conftest.py, at the top of tests/"


def test_every_subpackage_of_soadyn_has_its_test_folder():
    subpackages = sorted(path.parent.name for path in PACKAGE.glob("*/__init__.py")
                         if not path.parent.name.startswith("_"))
    assert {"io", "campaign"} <= set(subpackages)
    missing = [name for name in subpackages if name not in CONCERNS]
    assert not missing, f"soadyn subpackages without a folder of tests: {missing}"
