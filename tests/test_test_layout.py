"""Test modules stand alone: no Python file under tests/ imports a test module (a file named test_*.py).
Helpers shared between tests live in support/ or in the library modules beside the tests (trees.py,
robots.py, ...), so that running, moving or deleting one test file touches no other."""
from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).resolve().parent


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


def test_no_test_module_imports_another_test_module():
    sources = sorted(TESTS.rglob("*.py"))
    assert TESTS / "conftest.py" in sources and TESTS / "support" / "forked.py" in sources
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
