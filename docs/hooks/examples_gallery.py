"""MkDocs hook: the examples gallery, made by running the examples when the manual is built.

Each example is a script (or a `soadyn` command) that prints its results and writes a plot; the hook
runs it in a scratch folder and writes a page with the run command, what it printed, its plot and its
source. A failing example fails the build. With SOADYN_DOCS_QUICK=1 in the environment (the test suite's
build), examples that take a size option run at a reduced size.
"""
from __future__ import annotations

import ast
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]
TIMEOUT = 600  # seconds per example


class Example:
    def __init__(self, name: str, title: str, source: str, argv: list[str], quick: list[str] = (),
                 shown: str | None = None):
        self.name, self.title, self.source, self.argv, self.quick = name, title, source, argv, list(quick)
        self.shown = shown  # the command as a reader types it

    def run(self, folder: Path) -> tuple[str, bytes]:
        """(what it printed, the PNG it wrote)."""
        png = folder / f"{self.name}.png"
        argv = [a.replace("{png}", str(png)) for a in self.argv]
        if os.environ.get("SOADYN_DOCS_QUICK") == "1":
            argv += self.quick
        result = subprocess.run([sys.executable, *argv], cwd=folder, capture_output=True, text=True,
                                timeout=TIMEOUT, env=dict(os.environ, MPLBACKEND="Agg"))
        if result.returncode != 0:
            raise RuntimeError(f"example {self.name} failed: {result.stderr[-2000:]}")
        return result.stdout, png.read_bytes()

    def page(self, printed: str) -> str:
        doc = ast.get_docstring(ast.parse((ROOT / self.source).read_text())) or ""
        summary = doc.split("\n\n    python")[0].strip()
        return "\n".join([
            f"# {self.title}\n", summary + "\n", "Run it:\n", f"```sh\n{self.shown}\n```\n",
            "It prints (this run was made when the manual was built):\n", f"```text\n{printed.rstrip()}\n```\n",
            f"![{self.title}]({self.name}.png)\n", "## The source\n",
            f"`{self.source}`:\n", f'```python\n--8<-- "{self.source}"\n```\n'])


EXAMPLES = [
    Example("four-bar", "The four-bar of Saha, Shah & Nandihal", "python/soadyn/apps/four_bar_demo.py",
            ["-m", "soadyn", "demo", "--scene", "four-bar", "--plot", "{png}"],
            shown="soadyn demo --scene four-bar --plot four-bar.png"),
    Example("stanford-arm", "The Stanford arm: drive forces and a free fall", "examples/python/stanford_arm.py",
            [str(ROOT / "examples/python/stanford_arm.py"), "--plot", "{png}"], ["--duration", "2"],
            shown="python examples/python/stanford_arm.py --plot stanford-arm.png"),
    Example("cassini-lockup", "Cassini: an actuator lock-up fault", "examples/python/cassini_lockup.py",
            [str(ROOT / "examples/python/cassini_lockup.py"), "--plot", "{png}"], ["--duration", "2", "--lock-time", "1"],
            shown="python examples/python/cassini_lockup.py --plot cassini-lockup.png"),
    Example("slider-crank", "The slider-crank: drive torque and pin force", "examples/python/slider_crank.py",
            [str(ROOT / "examples/python/slider_crank.py"), "--plot", "{png}"], ["--samples", "73"],
            shown="python examples/python/slider_crank.py --plot slider-crank.png"),
    Example("solar-wing", "A solar wing deploys, latches and rings", "examples/python/solar_panel_deployment.py",
            [str(ROOT / "examples/python/solar_panel_deployment.py"), "--plot", "{png}"],
            shown="python examples/python/solar_panel_deployment.py --plot solar-wing.png"),
    Example("monte-carlo-campaign", "A Monte Carlo campaign on Dask", "examples/python/monte_carlo_campaign.py",
            [str(ROOT / "examples/python/monte_carlo_campaign.py"), "--plot", "{png}"], ["--runs", "6"],
            shown="python examples/python/monte_carlo_campaign.py --plot monte-carlo-campaign.png"),
    Example("flexible-spacecraft-modes", "A flexible spacecraft's modes", "examples/python/flexible_spacecraft_modes.py",
            [str(ROOT / "examples/python/flexible_spacecraft_modes.py"), "--plot", "{png}"],
            shown="python examples/python/flexible_spacecraft_modes.py --plot flexible-spacecraft-modes.png"),
    Example("analysis", "Equilibrium, design sensitivity, LQR and modes", "examples/python/analysis_worked_example.py",
            [str(ROOT / "examples/python/analysis_worked_example.py"), "--plot", "{png}"],
            shown="python examples/python/analysis_worked_example.py --plot analysis.png"),
]


def index() -> str:
    lines = ["# Examples\n", "Each example runs when this manual is built; its page shows what it printed, its "
             "plot and its source.\n"]
    lines += [f"- [{e.title}]({e.name}.md)" for e in EXAMPLES]
    return "\n".join(lines) + "\n"


def on_files(files, config):
    files.append(File.generated(config, "examples/index.md", content=index()))
    with tempfile.TemporaryDirectory(prefix="soadyn-examples-") as folder:
        for example in EXAMPLES:
            printed, png = example.run(Path(folder))
            files.append(File.generated(config, f"examples/{example.name}.md", content=example.page(printed)))
            files.append(File.generated(config, f"examples/{example.name}.png", content=png))
    return files
