"""MkDocs hook: the C++ reference (reference/cpp.md), an index of the public headers written at build time
from the headers themselves: each header under cpp/include/soadyn with the comment it opens with, folder
by folder in the include order of the layout (docs/design/layout.md), so the page says what the headers
say."""
from __future__ import annotations

from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]
INCLUDE = ROOT / "cpp" / "include"
FOLDERS = ("", "core", "spatial", "linalg", "joints", "flex", "model", "sweeps", "algorithms", "constraints", "sim",
           "analysis", "realtime", "parallel")


def leading_comment(header: Path) -> str:
    """The // comment lines a header opens with, joined into one paragraph ("" if none)."""
    lines = []
    for line in header.read_text().splitlines():
        if line.startswith("//"):
            lines.append(line[2:].strip())
        elif lines or (line.strip() and not line.startswith("#pragma")):
            break
    text = " ".join(x for x in lines if x).strip()
    return text.replace("[", "\\[").replace("]", "\\]")  # brackets in formulas are not links


def cpp_reference() -> str:
    parts = ["# C++ headers\n",
             "Generated from `cpp/include/soadyn` when this manual is built: every public header with the "
             "comment it opens with. `#include <soadyn/soadyn.hpp>` brings them all; how to build and link: "
             "[the C++ guide](../guides/cpp.md). The `.hxx` files beside some headers hold their template "
             "definitions.\n"]
    headers = sorted(INCLUDE.glob("soadyn/**/*.hpp"))
    placed = set()
    for folder in FOLDERS:
        inside = [h for h in headers if h.parent == INCLUDE / "soadyn" / folder] if folder else \
            [h for h in headers if h.parent == INCLUDE / "soadyn"]
        if not inside:
            continue
        parts.append(f"## `soadyn/{folder + '/' if folder else ''}`\n")
        parts += [f"- `{h.relative_to(INCLUDE)}`: {leading_comment(h) or '(no leading comment)'}" for h in inside]
        parts.append("")
        placed.update(inside)
    rest = [h for h in headers if h not in placed]
    if rest:
        parts.append("## Other folders\n")
        parts += [f"- `{h.relative_to(INCLUDE)}`: {leading_comment(h) or '(no leading comment)'}" for h in rest]
    return "\n".join(parts) + "\n"


def on_files(files, config):
    files.append(File.generated(config, "reference/cpp.md", content=cpp_reference()))
    return files
