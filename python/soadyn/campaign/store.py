"""The results directory of a campaign, written incrementally (Parquet, pyarrow).

    DIR/spec.toml           the spec as given (when it was a file)
    DIR/spec.json           the checked spec (every number resolved), the model's SHA-256, the software
    DIR/model.json          the model-file text every run built its model from
    DIR/runs/part-*.parquet one file per finished batch of runs: run_id, the dispersed values, the
                            metrics, status ("ok" or "failed"), message
    DIR/trajectories/run_id=<i>/part.parquet   decimated trajectories (t, q:<coordinate>, v:<DOF>)
    DIR/results.parquet     every run, sorted by run_id, once the campaign is complete

Every file is written under a temporary name and renamed (os.replace), so a killed campaign
leaves whole files only; a batch's trajectories are written before its runs part, so a run in
a part always has its trajectory. A campaign started again on the same DIR reads the parts,
skips the runs they hold and runs the others: the same spec resumes, the same spec with more
runs extends the campaign (run i does not depend on the number of runs). A DIR holding another
spec, or this spec with more runs than now asked for, is refused: its results never shrink.
"""
from __future__ import annotations

import json
import os
import platform
import uuid
from pathlib import Path
from typing import Optional

import numpy as np

from .._soadyn import _appendage_kernel, _joint_angle_kernel, _mass_matrix_kernel
from .._version import __version__
from ..bounded_input import check_json, read_text
from ..output_paths import output_problem
from .errors import CampaignError, ResultsDirectoryError

SPEC_JSON = "spec.json"
MODEL_JSON = "model.json"
RESULTS = "results.parquet"


def _pa():
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError as error:
        raise CampaignError(f"campaign results need pyarrow (pip install 'soadyn[campaign]'): {error}") from None
    return pyarrow


def schema(spec):
    pa = _pa()
    return pa.schema([("run_id", pa.int64()), *((c, pa.float64()) for c in spec.dispersion_columns),
                      *((m, pa.float64()) for m in spec.metrics), ("status", pa.string()), ("message", pa.string())])


def rows_table(spec, rows: list):
    pa = _pa()
    sch = schema(spec)
    return pa.table({name: pa.array([row[name] for row in rows], type=sch.field(name).type) for name in sch.names},
                    schema=sch)


def trajectory_table(spec, trajectory: dict):
    pa = _pa()
    columns = {"t": trajectory["t"]}
    columns.update({f"q:{n}": trajectory["q"][:, k] for k, n in enumerate(spec.coordinate_names)})
    columns.update({f"v:{n}": trajectory["v"][:, k] for k, n in enumerate(spec.dof_names)})
    return pa.table({k: pa.array(np.ascontiguousarray(v, dtype=float)) for k, v in columns.items()})


def software() -> dict:
    versions = {"soadyn": __version__, "numpy": np.__version__, "python": platform.python_version(),
                "joint_angle_kernel": _joint_angle_kernel(), "mass_matrix_kernel": _mass_matrix_kernel(),
                "appendage_kernel": _appendage_kernel()}
    try:
        import pyarrow

        versions["pyarrow"] = pyarrow.__version__
    except ImportError:
        pass
    return versions


def resolved(spec) -> dict:
    """The content of spec.json."""
    return {"format": "soadyn-campaign-results", "version": 1, "spec": spec.normalized,
            "identity": spec.identity(), "model_sha256": spec.model_sha256, "columns": spec.columns,
            "software": software()}


def _write_atomic(path: Path, write) -> None:
    """write(tmp) then rename: readers and a later resume never see half a file."""
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def _write_text(path: Path, text: str) -> None:
    _write_atomic(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def _write_parquet(path: Path, table) -> None:
    import pyarrow.parquet as pq

    _write_atomic(path, lambda tmp: pq.write_table(table, tmp))


def _ours_before_spec_json(path: Path) -> bool:
    """What a campaign killed while creating its directory (before spec.json) may have left."""
    name = path.name
    if name in ("spec.toml", MODEL_JSON, ".DS_Store") or (name.startswith(".") and name.endswith(".tmp")):
        return True
    return path.name in ("runs", "trajectories") and path.is_dir() and not any(path.iterdir())


class MemoryStore:
    """Results kept in memory (run() without a results directory): nothing to resume."""

    out = None

    def __init__(self, spec):
        self.spec = spec
        self.rows: dict = {}
        self.trajectories: dict = {}

    def open(self) -> set:
        return set()

    def add(self, outcomes) -> None:
        for outcome in outcomes:
            self.rows[outcome.row["run_id"]] = outcome.row
            if outcome.trajectory is not None:
                self.trajectories[outcome.row["run_id"]] = trajectory_table(self.spec, outcome.trajectory)

    def table(self):
        return rows_table(self.spec, [self.rows[i] for i in sorted(self.rows) if i < self.spec.runs])

    def finish(self):
        return self.table()


class DirectoryStore:
    """The results directory `out` (see the module's docstring)."""

    def __init__(self, spec, out):
        self.spec = spec
        self.out = Path(out)
        self.runs_dir = self.out / "runs"
        self.trajectories_dir = self.out / "trajectories"
        self.trajectories: dict = {}  # run_id -> table: only those written in this session (read them from DIR)
        self._done: set = set()

    def open(self) -> set:
        """Create DIR, or check it holds this spec; the run ids already done."""
        _pa()
        out = self.out
        problem = output_problem(out, directory=True)
        if problem:
            raise ResultsDirectoryError(f"{out}: {problem}")
        stored = out / SPEC_JSON
        if stored.exists():
            self._check_same_spec(stored)
        elif out.exists() and any(not _ours_before_spec_json(p) for p in out.iterdir()):
            raise ResultsDirectoryError(f"{out} is not empty and holds no campaign ({SPEC_JSON} is missing): "
                                        f"give a new or empty directory")
        self.runs_dir.mkdir(parents=True, exist_ok=True)
        if self.spec.trajectory_every:
            self.trajectories_dir.mkdir(exist_ok=True)
        for leftover in [*out.glob(".*.tmp"), *self.runs_dir.glob(".*.tmp"), *self.trajectories_dir.glob("*/.*.tmp")]:
            leftover.unlink()  # what a killed campaign was writing
        if not stored.exists():
            if self.spec.text is not None:
                _write_text(out / "spec.toml", self.spec.text)
            _write_text(out / MODEL_JSON, self.spec.model_json)
        # (re)written: the same identity, but maybe another number of runs
        _write_text(stored, json.dumps(resolved(self.spec), indent=2, allow_nan=False) + "\n")
        self._done = set(int(i) for i in read_parts(self.out, self.spec)["run_id"].to_pylist())
        if not set(range(self.spec.runs)) <= self._done and (out / RESULTS).exists():
            (out / RESULTS).unlink()  # a complete campaign of fewer runs: rewritten when this one completes
        return set(self._done)

    def _check_same_spec(self, stored: Path) -> None:
        """The campaign in DIR is this spec's with at most as many runs: it resumes or grows, never
        shrinks (its finished runs would drop out of results.parquet and the report)."""
        try:
            previous = stored_json(stored, ResultsDirectoryError)
            identity, runs = previous["identity"], previous["spec"]["runs"]
        except (OSError, ValueError, KeyError, TypeError) as error:
            raise ResultsDirectoryError(f"{stored}: unreadable campaign description: {error}") from None
        current = json.loads(json.dumps(self.spec.identity()))
        if identity != current:
            differing = sorted(k for k in set(identity) | set(current) if identity.get(k) != current.get(k))
            raise ResultsDirectoryError(f"{self.out} holds the results of another spec (it differs in: "
                                        f"{', '.join(differing)}); give another directory, or delete this one")
        if isinstance(runs, int) and self.spec.runs < runs:
            raise ResultsDirectoryError(f"{self.out} holds a campaign of {runs} runs of this spec: {self.spec.runs} "
                                        f"runs would shrink it; give runs >= {runs} (the same number resumes it, "
                                        f"more extend it), or another directory")

    def add(self, outcomes) -> None:
        """One finished batch: its trajectories, then its runs part."""
        outcomes = [o for o in outcomes if o.row["run_id"] not in self._done]
        if not outcomes:
            return
        for outcome in outcomes:
            if outcome.trajectory is not None:
                run_dir = self.trajectories_dir / f"run_id={outcome.row['run_id']}"
                run_dir.mkdir(parents=True, exist_ok=True)
                _write_parquet(run_dir / "part.parquet", trajectory_table(self.spec, outcome.trajectory))
        ids = sorted(o.row["run_id"] for o in outcomes)
        part = self.runs_dir / f"part-{ids[0]:08d}-{ids[-1]:08d}.parquet"
        while part.exists():
            part = part.with_name(f"part-{ids[0]:08d}-{ids[-1]:08d}-{uuid.uuid4().hex[:6]}.parquet")
        _write_parquet(part, rows_table(self.spec, sorted((o.row for o in outcomes), key=lambda r: r["run_id"])))
        self._done.update(ids)

    def table(self):
        return read_parts(self.out, self.spec, self.spec.runs)

    def finish(self):
        """results.parquet: every run of the spec, sorted by run_id."""
        table = self.table()
        _write_parquet(self.out / RESULTS, table)
        return table


def read_parts(out, spec, runs: Optional[int] = None):
    """The runs parts of `out` as one table sorted by run_id (runs < `runs` if given)."""
    pa = _pa()
    import pyarrow.parquet as pq

    sch = schema(spec)
    tables = []
    for part in sorted((Path(out) / "runs").glob("part-*.parquet")):
        try:
            table = pq.read_table(part)
        except (OSError, pa.ArrowException) as error:
            raise CampaignError(f"{part}: unreadable results part: {error}") from None
        if table.schema != sch:
            raise CampaignError(f"{part}: its columns are not those of the spec in {Path(out) / SPEC_JSON}")
        tables.append(table)
    table = pa.concat_tables(tables) if tables else sch.empty_table()
    if runs is not None:
        import pyarrow.compute as pc

        table = table.filter(pc.less(table["run_id"], runs))
    table = table.sort_by("run_id")
    ids = table["run_id"].to_numpy()
    if len(ids) > 1 and np.any(ids[1:] == ids[:-1]):
        # the same run in two parts (two campaigns writing one DIR at once): identical rows, keep one
        keep = np.concatenate([[True], ids[1:] != ids[:-1]])
        table = table.filter(pa.array(keep))
    return table.combine_chunks()


def read_trajectory(out, run_id: int):
    """The stored trajectory of one run (a pyarrow Table), or None."""
    import pyarrow.parquet as pq

    path = Path(out) / "trajectories" / f"run_id={run_id}" / "part.parquet"
    return pq.read_table(path) if path.exists() else None


def stored_json(path: Path, error: type):
    """The JSON a results directory keeps at `path`, read within soadyn.bounded_input's size and depth limits
    (`error` naming the file beyond them)."""
    text = read_text(path, str(path), error, "campaign description")
    check_json(text, str(path), error)
    return json.loads(text)


def read_stored(out) -> tuple:
    """(spec.json content, model.json text) of a results directory; CampaignError naming what is missing."""
    out = Path(out)
    for name in (SPEC_JSON, MODEL_JSON):
        if not (out / name).exists():
            raise CampaignError(f"{out} is not a campaign results directory ({name} is missing)")
    try:
        description = stored_json(out / SPEC_JSON, CampaignError)
        model_json = read_text(out / MODEL_JSON, str(out / MODEL_JSON), CampaignError, "campaign's model")
    except (OSError, ValueError) as error:
        raise CampaignError(f"{out}: unreadable campaign description: {error}") from None
    if not isinstance(description, dict) or description.get("format") != "soadyn-campaign-results":
        raise CampaignError(f"{out / SPEC_JSON}: not a soadyn campaign description")
    return description, model_json
