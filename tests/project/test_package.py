"""The installed package: submodules reachable as attributes, type stubs that
match the compiled module, no mutable default arguments, and the optional
progress display."""
import ast
import inspect
import io
import pathlib
import subprocess
import sys

import pytest

import soadyn
from soadyn import _soadyn
from soadyn.progress import PlainProgress

PACKAGE = pathlib.Path(soadyn.__file__).parent


def test_scenes_and_hil_are_attributes_after_import_soadyn():
    code = "import soadyn; print(soadyn.scenes.SCENES is not None, callable(soadyn.hil.run_hil))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "True"]


def _stub_tree():
    return ast.parse((PACKAGE / "_soadyn.pyi").read_text())


def _stub_names(tree):
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
    return names


PYBIND11_INTERNAL = {"_pybind11_conduit_v1_"}  # pybind11's own cross-module hook on every class


def _named(names):
    """Names other than dunders and pybind11's own."""
    return {n for n in names if not (n.startswith("__") and n.endswith("__")) and n not in PYBIND11_INTERNAL}


def test_stub_and_py_typed_are_installed():
    assert (PACKAGE / "py.typed").is_file()
    assert (PACKAGE / "_soadyn.pyi").is_file()


def test_stub_names_the_compiled_modules_attributes():
    stub = _named(_stub_names(_stub_tree()))
    module = _named(dir(_soadyn))
    assert {n for n in module if not n.startswith("_")} <= stub  # every public name, as the issue asks
    assert stub == module  # and the private ones the package uses, both ways


def test_stub_classes_name_their_members():
    classes = [node for node in _stub_tree().body if isinstance(node, ast.ClassDef)]
    assert {node.name for node in classes} == {n for n in dir(_soadyn) if isinstance(getattr(_soadyn, n), type)}
    for node in classes:
        assert _named(_stub_names(node)) == _named(vars(getattr(_soadyn, node.name))), node.name


def test_stub_functions_take_the_modules_parameters():
    for node in _stub_tree().body:
        if not isinstance(node, ast.FunctionDef) or node.name.startswith("_"):
            continue
        stub_params = [a.arg for a in node.args.posonlyargs + node.args.args + node.args.kwonlyargs]
        fn = getattr(_soadyn, node.name)
        try:
            params = list(inspect.signature(fn).parameters)
        except ValueError:  # a pybind11 function: its first docstring line is its signature
            first = fn.__doc__.splitlines()[0]
            params = [p.split(":")[0].strip() for p in first[first.index("(") + 1:first.rindex(")")].split(", ")
                      if p.strip()]
            params = [p for p in params if p not in ("*", "/")]
        assert stub_params == params, node.name


def _mutable_defaults(path):
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            for default in node.args.defaults + [d for d in node.args.kw_defaults if d is not None]:
                if isinstance(default, (ast.List, ast.Dict, ast.Set, ast.Call)):
                    yield f"{path.name}:{default.lineno}: {ast.unparse(default)}"


def test_no_mutable_default_arguments():
    found = [hit for path in sorted(PACKAGE.glob("*.py")) for hit in _mutable_defaults(path)]
    assert found == []


def test_plain_progress_prints_counts_and_postfix():
    stream = io.StringIO()
    bar = PlainProgress(total=100, unit="step", desc="HIL", stream=stream)
    bar.update(40)
    bar.update(60 - bar.n)
    bar.set_postfix({"t": "0.06s", "misses": 0}, refresh=False)
    bar.close()
    assert bar.n == 60
    assert stream.getvalue() == "HIL: 60/100 steps, t=0.06s, misses=0\n"


def test_plain_progress_disabled_prints_nothing():
    stream = io.StringIO()
    bar = PlainProgress(total=10, unit="step", desc="HIL", disable=True, stream=stream)
    bar.update(10)
    bar.close()
    assert stream.getvalue() == ""


def test_progress_bar_falls_back_without_tqdm(monkeypatch):
    from soadyn import progress
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm raises ImportError
    bar = progress.progress_bar(5, unit="step", desc="HIL", disable=True)
    assert isinstance(bar, PlainProgress)


def test_progress_bar_is_tqdms_when_installed():
    import tqdm  # the test extra installs it
    bar = soadyn.progress.progress_bar(5, unit="step", desc="HIL", disable=True)
    assert isinstance(bar, tqdm.tqdm)
    bar.close()
