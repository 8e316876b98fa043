"""Every Python code block of README.md and the manual (docs/) runs as written.

The blocks of one page run in order in one namespace, as a reader goes through a page (a later block may
use what an earlier one made), in a scratch working directory (files a block writes land there). A block
that cannot run here is marked by an HTML comment on the line before its fence,
``<!-- not run: REASON -->``, with the reason (a cluster, a browser left open); a mark without a reason
fails, and so does a page whose every block is marked. Shell blocks are run elsewhere: the two README
commands by CI, the C++ guide's by the C++ tests (tests/cpp/installed_package.py).
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import matplotlib
import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("**/*.md"))]
BLOCK = re.compile(r"(?:^<!-- not run: ?(?P<reason>.*?) ?-->\n)?^```python\n(?P<code>.*?)^```$", re.MULTILINE | re.DOTALL)


def python_blocks(page: Path) -> list[tuple[str, str | None]]:
    """(code, reason not run or None) of every ```python block of a page."""
    return [(m.group("code"), m.group("reason")) for m in BLOCK.finditer(page.read_text())]


PAGES_WITH_CODE = [page for page in PAGES if python_blocks(page)]


@pytest.mark.parametrize("page", PAGES_WITH_CODE, ids=[str(p.relative_to(ROOT)) for p in PAGES_WITH_CODE])
def test_the_pages_python_blocks_run(page, tmp_path, monkeypatch):
    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    blocks = python_blocks(page)
    run = [code for code, reason in blocks if reason is None]
    assert run, f"{page.name}: every block is marked not run"
    for code, reason in blocks:
        assert reason is None or reason.strip(), f"{page.name}: a block is marked not run without a reason"
    namespace = {"__name__": f"docs_{page.stem}"}
    for k, code in enumerate(run):
        try:
            exec(compile(code, f"{page.relative_to(ROOT)} (block {k + 1})", "exec"), namespace)
        except Exception as error:
            raise AssertionError(f"{page.relative_to(ROOT)}, Python block {k + 1}:\n{code}\n{error!r}") from error


def test_the_documentation_holds_python_blocks():
    counted = sum(len(python_blocks(page)) for page in PAGES)
    skipped = sum(reason is not None for page in PAGES for _, reason in python_blocks(page))
    assert counted >= 19 and skipped <= 2, (counted, skipped)
    assert os.path.isdir(ROOT / "docs")
