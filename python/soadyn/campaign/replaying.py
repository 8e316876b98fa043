"""Replay one run of a results directory: recompute it from the stored spec and model-file
text and compare with the stored row (and trajectory) bit for bit."""
from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from .errors import CampaignError
from .simulate import run_one
from .spec import load_spec
from .store import read_parts, read_stored, read_trajectory, trajectory_table


@dataclass
class Replay:
    """What campaign.replay returns for one run: each stored column beside its recomputed value and whether
    the two are bit-identical, the same for the kept trajectory, and `equal` when everything is."""

    run_id: int
    values: list                   # (column, stored or None, recomputed, bit-identical)
    stored: bool                   # the run was found in the results
    trajectory_equal: Optional[bool]  # None: no trajectory kept
    outcome: object                # the recomputed simulate.RunOutcome

    @property
    def equal(self) -> bool:
        """Whether the run was stored and every recomputed value (and the trajectory, when kept) equals it bit for
        bit."""
        return self.stored and all(same for *_, same in self.values) and self.trajectory_equal is not False


def stored_spec(out):
    """The Spec a results directory was made with (from its spec.json and model.json)."""
    description, model_json = read_stored(out)
    spec = load_spec(description["spec"], base_dir=Path(out), model_json=model_json)
    if spec.model_sha256 != description.get("model_sha256"):
        raise CampaignError(f"{Path(out) / 'model.json'}: its SHA-256 is not the one in spec.json")
    return spec


def replay(out, run_id: int) -> Replay:
    """Recompute run `run_id` of the campaign in `out`; ValueError for a run id out of range."""
    spec = stored_spec(out)
    if isinstance(run_id, bool) or not isinstance(run_id, int) or not 0 <= run_id < spec.runs:
        raise ValueError(f"run id must be an integer in 0..{spec.runs - 1}, got {run_id!r}")
    table = read_parts(out, spec)
    rows = table.filter(table["run_id"].to_numpy() == run_id).to_pylist()
    stored = rows[0] if rows else None
    outcome = run_one(spec, run_id)
    values = []
    for column in spec.columns:
        new = outcome.row[column]
        old = stored[column] if stored else None
        values.append((column, old, new, stored is not None and _same(old, new)))
    trajectory_equal = None
    if spec.trajectory_every and stored is not None:
        kept = read_trajectory(out, run_id)
        if outcome.trajectory is None:
            trajectory_equal = kept is None
        else:
            trajectory_equal = kept is not None and kept.equals(trajectory_table(spec, outcome.trajectory))
    return Replay(run_id, values, stored is not None, trajectory_equal, outcome)


def _same(a, b) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        return struct.pack("<d", a) == struct.pack("<d", b)
    return a == b and type(a) is type(b)


def format_replay(r: Replay) -> str:
    """A Replay as the text table `soadyn campaign replay` prints: column, stored, recomputed, bit-identical."""
    def show(x):
        return "-" if x is None else repr(x) if isinstance(x, float) else str(x)

    width = max(len(c) for c, *_ in r.values)
    rows = [(c, show(old) if r.stored else "(not stored)", show(new), "yes" if same else "NO")
            for c, old, new, same in r.values]
    w1 = max(len("stored"), *(len(x[1]) for x in rows))
    w2 = max(len("recomputed"), *(len(x[2]) for x in rows))
    lines = [f"{'column':<{width}}  {'stored':<{w1}}  {'recomputed':<{w2}}  bit-identical"]
    lines += [f"{c:<{width}}  {a:<{w1}}  {b:<{w2}}  {s if r.stored else '-'}" for c, a, b, s in rows]
    if r.trajectory_equal is not None:
        lines.append(f"trajectory: {'bit-identical' if r.trajectory_equal else 'DIFFERENT'}")
    if not r.stored:
        lines.append(f"run {r.run_id} is not in the results yet (the campaign has not run it): recomputed only")
    elif r.equal:
        lines.append(f"run {r.run_id}: the recomputed values equal the stored ones bit for bit")
    else:
        lines.append(f"run {r.run_id}: the recomputed values DIFFER from the stored ones")
    return "\n".join(lines)
