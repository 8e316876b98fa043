"""Results as data: each benchmark writes one JSON file to bench/results/.

A file holds the benchmark's name and title, the command, the date (UTC), the
commit of the checkout, facts about the machine (processor model, logical
cores, architecture: no paths, no user names), the settings of the run, and
its tables. A table is a title, its column labels, one number format per
numeric column, its rows (lists in column order) and the labels of its
headline columns (the ratios bench/summary.py collects into SUMMARY.md).
The same tables are printed to stdout as markdown.
"""
from __future__ import annotations

import json
import os
import platform
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


@dataclass
class Table:
    """One table of results. `formats` maps a column label to a format spec for numbers (".2f", ",.0f", ".1e",
    "g"); values are stored rounded as printed. `key`: how many leading columns name a row. `summary`: whether
    SUMMARY.md shows it (default: when it has headline columns)."""
    title: str
    columns: list[str]
    formats: dict[str, str] = field(default_factory=dict)
    rows: list[list] = field(default_factory=list)
    headline: list[str] = field(default_factory=list)
    key: int = 1
    summary: bool | None = None

    def add(self, *values) -> list:
        if len(values) != len(self.columns):
            raise ValueError(f"{self.title}: {len(values)} values for {len(self.columns)} columns")
        row = [stored(v, self.formats.get(c)) for c, v in zip(self.columns, values)]
        self.rows.append(row)
        return row

    def markdown(self, columns: list[str] | None = None, bold: bool = True) -> list[str]:
        """The table (or the named columns of it) as markdown lines, headline columns in bold (if `bold`)."""
        columns = columns or self.columns
        index = [self.columns.index(c) for c in columns]
        bold = [bold and c in self.headline for c in columns]
        header = "| " + " | ".join(f"**{c}**" if b else c for c, b in zip(columns, bold)) + " |"
        numeric = [any(isinstance(row[i], (int, float)) and not isinstance(row[i], bool) for row in self.rows)
                   for i in index]
        rule = "|" + "".join("---:|" if k >= self.key and numeric[k] else "---|" for k in range(len(columns)))
        lines = [header, rule]
        for row in self.rows:
            cells = [shown(row[i], self.formats.get(self.columns[i])) for i in index]
            lines.append("| " + " | ".join(f"**{c}**" if b and c != "n/a" else c for c, b in zip(cells, bold)) + " |")
        return lines

    def print(self) -> None:
        print(f"\n{self.title}\n", *self.markdown(), sep="\n", flush=True)

    def as_dict(self) -> dict:
        out = {"title": self.title, "columns": self.columns, "formats": self.formats, "key": self.key,
               "headline": self.headline, "rows": self.rows}
        if self.summary is not None:
            out["summary"] = self.summary
        return out

    @classmethod
    def from_dict(cls, d: dict) -> "Table":
        return cls(d["title"], d["columns"], d.get("formats", {}), d.get("rows", []), d.get("headline", []),
                   d.get("key", 1), d.get("summary"))

    def in_summary(self) -> bool:
        return bool(self.headline) if self.summary is None else self.summary


def stored(value, fmt: str | None):
    """A value as the results file keeps it: numbers rounded as `fmt` prints them; None and NaN as None."""
    if value is None or isinstance(value, (str, bool)):
        return value
    value = float(value)
    if value != value:
        return None
    if fmt is None or fmt == "g":
        return int(value) if value.is_integer() and abs(value) < 2**53 else float(f"{value:.6g}")
    text = format(value, fmt.replace(",", ""))
    return int(text) if fmt.endswith(".0f") else float(text)


def shown(value, fmt: str | None) -> str:
    """A stored value as a table cell."""
    if value is None:
        return "n/a"
    if isinstance(value, str) or fmt is None:
        return str(value)
    return format(value, fmt)


def now() -> str:
    return time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())


def commit() -> str | None:
    """The commit checked out (short hash), None outside a git checkout."""
    out = subprocess.run(["git", "-C", str(HERE), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return out.stdout.strip() or None if out.returncode == 0 else None


def machine() -> dict:
    """The processor's model name, its logical cores and architecture."""
    cpu = platform.processor() or "unknown"
    try:
        with open("/proc/cpuinfo") as info:
            cpu = next((l.split(":", 1)[1].strip() for l in info if l.startswith("model name")), cpu)
    except OSError:
        pass
    return {"cpu": cpu, "logical_cores": os.cpu_count(), "architecture": platform.machine()}


def repo_path(path) -> Path:
    """A path as seen from the repository's root (its name alone outside the repository): no machine's folders."""
    path = Path(path).resolve()
    return path.relative_to(HERE.parent) if path.is_relative_to(HERE.parent) else Path(path.name)


def command(argv: list[str] | None = None) -> str:
    """The command line that ran this benchmark, from the repository's root."""
    argv = sys.argv if argv is None else argv
    return " ".join(["python", f"bench/{Path(argv[0]).name}", *map(shlex.quote, argv[1:])])


def write(name: str, title: str, tables: list[Table], settings: dict | None = None, notes: list[str] = (),
          extra: dict | None = None, command_line: str | None = None) -> Path:
    """Writes bench/results/<name>.json and says so."""
    data = {"benchmark": name, "title": title, "command": command_line or command(), "date": now(),
            "commit": commit(), "machine": machine(), "settings": settings or {}, "notes": list(notes),
            "tables": [t.as_dict() for t in tables]}
    if extra:
        data.update(extra)
    return save(name, data)


def save(name: str, data: dict) -> Path:
    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / f"{name}.json"
    path.write_text(dumps(data) + "\n")
    print(f"wrote bench/results/{path.name}")
    return path


def dumps(value, indent: str = "") -> str:
    """JSON with one line per list of plain values (a table's row, its columns), nested objects indented."""
    inner = indent + "  "
    if isinstance(value, dict) and value:
        items = [f"{inner}{json.dumps(k)}: {dumps(v, inner)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + indent + "}"
    if isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
        return "[\n" + ",\n".join(inner + dumps(v, inner) for v in value) + "\n" + indent + "]"
    return json.dumps(value, ensure_ascii=False)


def cell_value(text: str):
    """A markdown cell as a value: a number (bold, thousands separators, a trailing 'x' dropped), None for
    n/a or '-', else the text."""
    text = text.strip().strip("*").strip()
    if text in ("", "-", "n/a", "nan"):
        return None
    number = text.replace(",", "").removesuffix("x")
    try:
        return int(number) if number.lstrip("+-").isdigit() else float(number)
    except ValueError:
        return text


def cell_format(cells: list[str]) -> str | None:
    """The format that prints a column's numeric cells as the markdown shows them (None: not numeric)."""
    numbers = [c.strip().strip("*").strip() for c in cells if isinstance(cell_value(c), (int, float))]
    if not numbers:
        return None
    if any("e" in n.lower() for n in numbers):
        digits = max(len(n.lower().split("e")[0].split(".")[1]) if "." in n else 0 for n in numbers)
        sign = "+" if all(n[0] in "+-" for n in numbers) else ""
        return f"{sign}.{digits}e" if all("e" in n.lower() for n in numbers) else "g"
    decimals = max(len(n.split(".")[1].removesuffix("x")) if "." in n else 0 for n in numbers)
    return f"{',' if any(',' in n for n in numbers) else ''}.{decimals}f"


def tables_from_markdown(text: str, titles: list[str] = (), key: int | list[int] = 1) -> tuple[list[Table], list[str]]:
    """The markdown tables in `text` (a C++ benchmark's output) and its other non-empty lines. Headline
    columns: those whose cells are bold or whose label is a ratio (' / ')."""
    tables, notes, block = [], [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            block.append([c.strip() for c in line.strip().strip("|").split("|")])
            continue
        if block:
            header, rows = block[0], block[2:]
            columns = [c.strip("*").strip() for c in header]
            k = len(tables)
            table = Table(titles[k] if k < len(titles) else f"Table {k + 1}", columns,
                          key=key[k] if isinstance(key, list) else key)
            for c, label in enumerate(columns):
                cells = [r[c] for r in rows]
                fmt = cell_format(cells)
                if fmt:
                    table.formats[label] = fmt
                if " / " in label or (cells and all(x.startswith("**") for x in cells)):
                    table.headline.append(label)
            table.rows = [[cell_value(x) for x in r] for r in rows]
            tables.append(table)
            block = []
        if line.strip() and not line.startswith("|"):
            notes.append(line.strip())
    return tables, notes


def load(path: Path) -> tuple[dict, list[Table]]:
    data = json.loads(Path(path).read_text())
    return data, [Table.from_dict(t) for t in data.get("tables", [])]
