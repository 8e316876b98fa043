"""The manual builds, and the README stays the front door.

- `mkdocs build --strict` (the command the README gives) builds the site from docs/ with warnings as
  errors: a broken link or anchor, a page left out of the navigation, an API name mkdocstrings cannot
  find fails it. The Python API page documents the public names of `soadyn` (read from the code and the
  generated stub), and each module page of the reference every name of its module's __all__ (mkdocstrings
  leaves out a name without a docstring, so this fails on an undocumented public name); the command-line
  page, made from the parsers at build time, every command; the design pages include CONTRIBUTING.md;
  the C++ page indexes the public headers with their leading comments; the examples gallery runs every
  example (at a reduced size) and shows what each printed, its plot and its source.
- README.md is at most 250 lines, and every page of the manual it links to exists.
"""
from __future__ import annotations

import importlib
import os
import re
import subprocess
import sys
import types
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_manual_builds_with_warnings_as_errors(tmp_path):
    site = tmp_path / "site"
    result = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)], cwd=ROOT,
                            capture_output=True, text=True, timeout=600,
                            env=dict(os.environ, NO_MKDOCS_2_WARNING="1", SOADYN_DOCS_QUICK="1"))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    api = (site / "reference" / "python" / "index.html").read_text()
    documented = set(re.findall(r'id="soadyn\.(\w+)"', api))
    for name in ("Model", "Simulator", "Viewer", "hybrid_dynamics", "forward_kinematics", "load_urdf", "Trajectory"):
        assert name in documented, f"the API page does not document soadyn.{name}"
    for page in ("getting-started", "guides/hil", "guides/cpp", "gallery", "design/layout", "design/contributing"):
        assert (site / page / "index.html").is_file(), page
    undocumented = []
    for page in sorted((ROOT / "docs" / "reference").glob("*.md")):
        shown = set(re.findall(r'id="(soadyn[\w.]*)"', (site / "reference" / page.stem / "index.html").read_text()))
        for module_name in re.findall(r"^::: ([\w.]+)", page.read_text(), re.M):
            module = importlib.import_module(module_name)
            undocumented += [f"{module_name}.{name}" for name in module.__all__
                             if not isinstance(getattr(module, name), types.ModuleType)
                             and f"{module_name}.{name}" not in shown]
    assert not undocumented, f"public names without a docstring on their reference page: {undocumented}"
    cli = (site / "reference" / "cli" / "index.html").read_text()
    for command in ("demo", "check", "hil", "view", "campaign", "robots", "fmu"):
        assert f"soadyn {command}" in cli and "--screenshot" in cli, command
    assert "Adding a joint type" in (site / "design" / "contributing" / "index.html").read_text()
    for example in ("four-bar", "stanford-arm", "cassini-lockup", "slider-crank", "solar-wing", "monte-carlo-campaign",
                    "flexible-spacecraft-modes", "analysis"):  # run by the build: printed output, plot, source
        page = (site / "examples" / example / "index.html").read_text()
        assert "It prints" in page and "The source" in page and "import" in page, example
        assert (site / "examples" / f"{example}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", example
    headers = (site / "reference" / "cpp" / "index.html").read_text()
    assert "soadyn/algorithms/hybrid.hpp" in headers and "Jain &amp; Rodriguez" in headers
    assert "kinetic energy taken by the lock" in (site / "examples" / "cassini-lockup" / "index.html").read_text()
    assert "6 of 6 runs finished" in (site / "examples" / "monte-carlo-campaign" / "index.html").read_text()
    assert "peak |force|" in (site / "examples" / "stanford-arm" / "index.html").read_text()
    assert "the run's spectrum" in (site / "examples" / "solar-wing" / "index.html").read_text()
    assert "rigid-body modes at zero frequency" in (site / "examples" / "flexible-spacecraft-modes" / "index.html").read_text()


def reference_modules() -> list[str]:
    """The modules the reference pages render (their `::: module` lines)."""
    return [name for page in sorted((ROOT / "docs" / "reference").glob("*.md"))
            for name in re.findall(r"^::: ([\w.]+)", page.read_text(), re.M)]


def test_every_member_of_a_documented_class_has_a_docstring():
    """Properties and methods of the public classes the reference pages show, compiled ones included (a
    pybind11 method without its own text has only its signature as docstring)."""
    missing, seen = [], set()
    for module_name in reference_modules():
        module = importlib.import_module(module_name)
        for name in module.__all__:
            cls = getattr(module, name)
            if not isinstance(cls, type) or cls in seen:
                continue
            seen.add(cls)
            for member, value in vars(cls).items():
                value = value.__func__ if isinstance(value, (staticmethod, classmethod)) else value
                if member.startswith("_") or not (isinstance(value, property) or callable(value)):
                    continue
                doc = (getattr(value, "__doc__", None) or "").strip()
                first, _, rest = doc.partition("\n")
                if not doc or (first.startswith(f"{member}(") and "->" in first and not rest.strip()):
                    missing.append(f"{module_name}.{name}.{member}")
    assert not missing, f"members without a docstring: {missing}"


def test_the_readme_is_short_and_its_manual_links_resolve():
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 250
    links = re.findall(r"\]\((docs/[^)#]+)(?:#[^)]*)?\)", text)
    assert len(links) >= 20
    missing = [link for link in links if not (ROOT / link).is_file()]
    assert not missing, f"README links to missing pages: {missing}"
