"""The package's import rules, and its old module paths.

Read from the source with ast (nothing of the package is imported for these):
- no import cycle among the package's modules: every intra-package import counts, relative or absolute,
  `from . import x` as an import of the module x, imports inside functions included (the implicit import
  of a module's parent packages is not an edge);
- no module imports an underscore name from another module of the package, neither by `from m import _x`
  nor as `m._x` (the compiled soadyn._soadyn and the build's soadyn._version excepted);
- every intra-package import names a module, or a name of a module, that exists (the package's own code uses
  the new homes, not the old module paths).
Imported:
- every old module path of the alias table (soadyn._MOVED_MODULES: the package before it had subpackages)
  is the very module at its new home, in this process and in a fresh one, and no file is left at it;
- every name in soadyn.__all__, and in the __all__ of every module of the package, resolves.
"""
import ast
import importlib
import subprocess
import sys
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parents[2] / "python" / "soadyn"
# Modules that are no source here: the compiled module and the version file the build writes.
NOT_SOURCES = {"soadyn._soadyn", "soadyn._version"}
# The modules of the flat package (before it had subpackages): each still imports by that path.
OLD_MODULES = {
    "batch", "boom_vibration", "bounded_input", "check", "cli", "demo", "derivatives", "equilibrium_sensitivity",
    "four_bar_demo", "hil", "linearize", "loops", "mjcf", "model", "model_file", "modes", "mujoco_oracle",
    "oracles", "output_paths", "parameters", "pinocchio_mjcf", "progress", "scenes", "simulator", "statics",
    "text_files", "urdf", "urdf_export", "urdf_inertia", "urdf_reader", "urdf_visuals", "viewer", "visuals",
}


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE_DIR.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def sources() -> dict:
    """{module name: path} of the package's Python sources."""
    found = {module_name(p): p for p in sorted(PACKAGE_DIR.rglob("*.py"))}
    return {name: path for name, path in found.items() if name not in NOT_SOURCES}


def in_package(name: str) -> bool:
    return name == "soadyn" or name.startswith("soadyn.")


def is_private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def imports(module: str, path: Path, modules) -> list:
    """(imported module, name imported from it or None, line, (local name, the module it is bound to or None))
    of every intra-package import in the source of `module`."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found += [(alias.name, None, node.lineno,
                       (alias.asname, alias.name) if alias.asname else ("soadyn", "soadyn"))
                      for alias in node.names if in_package(alias.name)]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
                base = ".".join(base[:len(base) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module
            if not in_package(base):
                continue
            for alias in node.names:
                submodule, local = f"{base}.{alias.name}", alias.asname or alias.name
                if submodule in modules or submodule in NOT_SOURCES:
                    found.append((submodule, None, node.lineno, (local, submodule)))
                else:
                    found.append((base, alias.name, node.lineno, (local, None)))
    return found


def import_graph() -> tuple:
    """({module: {imported module: line}}, every intra-package import as (module, line, target, name))."""
    modules = sources()
    graph, every = {name: {} for name in modules}, []
    for module, path in modules.items():
        for target, name, line, _ in imports(module, path, modules):
            every.append((module, line, target, name))
            if target in modules and target != module:
                graph[module].setdefault(target, line)
    return graph, every


def cycles(graph: dict) -> list:
    """One cycle through each strongly connected component of more than one module (Tarjan)."""
    index, low, stack, on_stack, components = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                components.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    found = []
    for component in components:
        start = min(component)
        paths, seen = [[start]], {start}
        while paths:  # breadth first: the shortest way back to start within the component
            path = paths.pop(0)
            targets = [w for w in graph[path[-1]] if w in component]
            if start in targets:
                found.append(path + [start])
                break
            for w in targets:
                if w not in seen:
                    seen.add(w)
                    paths.append(path + [w])
    return found


def test_no_import_cycle_between_the_packages_modules():
    graph, _ = import_graph()
    assert len(graph) > 40  # the package's sources were found
    described = [" -> ".join(f"{a} (line {graph[a][b]})" for a, b in zip(cycle, cycle[1:])) + f" -> {cycle[-1]}"
                 for cycle in cycles(graph)]
    assert described == [], "import cycles:\n" + "\n".join(described)


def test_no_module_imports_a_private_name_of_another():
    modules = sources()
    found = []
    for module, path in modules.items():
        records = imports(module, path, modules)
        for target, name, line, _ in records:
            source, imported = (target, name) if name is not None else target.rsplit(".", 1)
            if target not in NOT_SOURCES and target != module and is_private(imported):
                found.append(f"{module} (line {line}) imports {imported} from {source}")
        bound = {local: target for _, _, _, (local, target) in records if target is not None}
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and is_private(node.attr)
                    and bound.get(node.value.id) not in (None, module, *NOT_SOURCES)):
                found.append(f"{module} (line {node.lineno}) uses {bound[node.value.id]}.{node.attr}")
    assert found == [], "private names used across modules:\n" + "\n".join(found)


def top_level_names(path: Path) -> set:
    """The names a source binds at its top level (in if and try blocks too)."""
    names, bodies = set(), [ast.parse(path.read_text(), str(path)).body]
    while bodies:
        for node in bodies.pop():
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                names.update(n.id for target in targets for n in ast.walk(target) if isinstance(n, ast.Name))
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                names.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
            elif isinstance(node, (ast.If, ast.Try)):
                bodies += [node.body, node.orelse, *[h.body for h in getattr(node, "handlers", [])],
                           getattr(node, "finalbody", [])]
    return names


def test_every_intra_package_import_names_a_module_or_name_that_exists():
    modules = sources()
    unknown = [f"{module} (line {line}) imports {target}" for module, line, target, _ in import_graph()[1]
               if target not in modules and target not in NOT_SOURCES]
    unknown += [f"{module} (line {line}) imports {name} from {target}, which has no such name or submodule"
                for module, line, target, name in import_graph()[1]
                if name is not None and target in modules and name not in top_level_names(modules[target])]
    assert unknown == [], "\n".join(unknown)


def test_old_module_paths_are_the_modules_at_their_new_homes():
    import soadyn

    moved = soadyn._MOVED_MODULES
    modules = sources()
    for old in OLD_MODULES:
        assert f"soadyn.{old}" in modules or f"soadyn.{old}" in moved, f"soadyn.{old} no longer imports"
    for old, new in moved.items():
        assert old not in modules and not (PACKAGE_DIR.parent / f"{old.replace('.', '/')}.py").exists(), old
        assert new in modules, f"{old} -> {new}: no such module"
        assert new.rsplit(".", 1)[1] == old.rsplit(".", 1)[1], f"{old} -> {new}: a moved module keeps its name"
        assert importlib.import_module(old) is importlib.import_module(new), old
        assert sys.modules[old] is sys.modules[new], old


FRESH_PROCESS = """
import importlib, sys
import soadyn
moved = soadyn._MOVED_MODULES
for old in moved:  # each old path first (the lazy ones through the finder), then its new home
    exec(f"import {old}")
    exec(f"from {old} import *")
for old, new in moved.items():
    assert sys.modules[old] is importlib.import_module(new), old
    short = old.rsplit(".", 1)[1]
    attribute = getattr(soadyn, short)
    assert attribute is sys.modules[new] or (short in soadyn.__all__ and callable(attribute)), old
assert callable(soadyn.modes) and callable(soadyn.linearize)  # functions of the names of old modules stay
print("ok")
"""


def test_old_module_paths_in_a_fresh_interpreter():
    out = subprocess.run([sys.executable, "-c", FRESH_PROCESS], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.split() == ["ok"], out.stderr


def test_old_command_module_paths_run_as_main():
    check = subprocess.run([sys.executable, "-m", "soadyn.check", "--help"], capture_output=True, text=True)
    assert check.returncode == 0 and check.stdout.startswith("usage: soadyn check"), check.stderr
    cli = subprocess.run([sys.executable, "-m", "soadyn.cli", "--version"], capture_output=True, text=True)
    assert cli.returncode == 0 and cli.stdout.startswith("soadyn "), cli.stderr


def test_every_name_in_all_resolves():
    import soadyn

    assert [n for n in soadyn.__all__ if not hasattr(soadyn, n)] == []
    assert len(set(soadyn.__all__)) == len(soadyn.__all__)  # each listed once
    for module in sources():
        if module.endswith("__main__"):
            continue  # running it is the command line
        names = getattr(importlib.import_module(module), "__all__", [])
        assert [n for n in names if not hasattr(sys.modules[module], n)] == [], module
