"""One version number: pyproject.toml's. The Python package and its metadata carry it; the C++ package's
(CMakeLists.txt reads pyproject.toml) is checked by the C++ test installed_package_install."""
import importlib.metadata
import re
from pathlib import Path

import soadyn

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def pyproject_version() -> str:
    text = PYPROJECT.read_text()
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        match = re.search(r'^\[project\][^\[]*?^version = "([^"]+)"', text, re.MULTILINE | re.DOTALL)
        assert match, "pyproject.toml has no version in [project]"
        return match.group(1)
    return tomllib.loads(text)["project"]["version"]


def test_python_package_version_is_pyproject_version():
    assert re.fullmatch(r"\d+\.\d+\.\d+", pyproject_version())
    assert soadyn.__version__ == pyproject_version()
    assert importlib.metadata.version("soadyn") == pyproject_version()


def test_cmake_reads_its_version_from_pyproject():
    """CMakeLists.txt writes no version of its own: project() takes the one it read from pyproject.toml."""
    cmake = (PYPROJECT.parent / "CMakeLists.txt").read_text()
    project = re.search(r"^project\(soadyn VERSION (\S+) ", cmake, re.MULTILINE)
    assert project and project.group(1) == "${CMAKE_MATCH_1}", project
    assert 'file(STRINGS "${CMAKE_CURRENT_SOURCE_DIR}/pyproject.toml"' in cmake
