"""soadyn.campaign.run: a campaign's runs on a Dask cluster, written as they finish.

Without a client, a dask.distributed LocalCluster of this machine (one single-threaded worker
process per core, or `workers`); with a scheduler address or a Client, any running Dask cluster
(dask-jobqueue's SLURM and PBS clusters included). The spec and its model-file text go to the
workers as data; each task runs a batch of runs (simulate.run_chunk) and returns rows and
trajectories, which this process writes (store.py), so workers need no shared file system.
"""
from __future__ import annotations

import contextlib
import logging
import math
import os
import signal
import threading
import time
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

from ..progress import PlainProgress, progress_bar
from .errors import CampaignError
from .simulate import RunOutcome, failed_outcome, run_chunk
from .simulate import run_one as _run_checked_one
from .spec import load_spec
from .store import DirectoryStore, MemoryStore, software

MAX_CHUNK = 50        # runs per task at most
TASKS_PER_WORKER = 8  # aim: this many tasks per worker (load balance, progress) unless chunks get too small
CONNECT_TIMEOUT = 30  # s to reach a scheduler


def run_one(spec, run_id: int) -> RunOutcome:
    """Run `run_id` of `spec` (a Spec, or what load_spec takes) here, without a cluster: its row of the
    results table and its decimated trajectory.

    Raises SpecError naming the item for a spec that does not check, and ValueError for a run_id that is
    not an integer in 0..runs-1. A run whose dynamics fail is a row with status "failed" and its message,
    not an exception.
    """
    spec = load_spec(spec)
    if isinstance(run_id, bool) or not isinstance(run_id, int) or not 0 <= run_id < spec.runs:
        raise ValueError(f"run id must be an integer in 0..{spec.runs - 1}, got {run_id!r}")
    return _run_checked_one(spec, run_id)


@dataclass
class CampaignResult:
    """What campaign.run returns: the table of every run of the spec (a pyarrow.Table sorted by run_id: the
    dispersed values, the metrics, status and message), where it was written, and how the call went."""

    table: object                 # pyarrow.Table: every run of the spec, sorted by run_id
    out: Optional[Path]           # the results directory (None: nothing written)
    runs: int
    done_before: int              # runs found already done in `out`
    computed: int                 # runs computed by this call
    failed: int                   # runs of the table with status "failed"
    seconds: float                # wall time of this call
    run_seconds: float            # of which running the pending runs (after the cluster was up)
    workers: int                  # workers when the runs were submitted
    dashboard_link: Optional[str]
    trajectories: dict = field(default_factory=dict)  # run_id -> pyarrow.Table (without `out`; else read DIR)


def run(spec, client=None, *, out=None, workers: Optional[int] = None, runs: Optional[int] = None,
        chunk_size: Optional[int] = None, progress: bool = True, verbose: bool = True, dashboard: bool = True,
        on_batch: Optional[Callable] = None) -> CampaignResult:
    """Run a campaign and return its results.

    `spec`: a spec file (TOML), a built-in example name ("cassini-example"), a dict or a Spec.
    `client`: None (a LocalCluster of `workers` processes, default one per core, closed at the
    end), a scheduler address ("tcp://host:8786") or a dask.distributed.Client (left open).
    `out`: the results directory (store.py): written as batches finish; a campaign started again
    on it resumes, skipping finished runs. None: results in memory only. `runs` overrides the spec's
    number of runs; `chunk_size` the runs per task. `on_batch(outcomes)` is called after each batch
    is stored. Failed runs are rows with status "failed"; SpecError / CampaignError before any run.
    """
    start = time.perf_counter()
    say = print if verbose else (lambda *a, **k: None)
    spec = load_spec(spec, runs=runs)
    if chunk_size is not None and (isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1):
        raise ValueError(f"chunk_size must be an integer >= 1, got {chunk_size!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    if workers is not None and client is not None:
        raise ValueError("workers sizes the local cluster; a client or scheduler address brings its own workers")
    store = DirectoryStore(spec, out) if out is not None else MemoryStore(spec)
    done = store.open() & set(range(spec.runs))
    pending = [i for i in range(spec.runs) if i not in done]
    dispersed = f"{len(spec.dispersions)} dispersed value{'s' * (len(spec.dispersions) != 1)}"
    say(f"campaign {spec.name}: {spec.runs} runs of {spec.duration:g} s ({spec.integrator}, dt {spec.dt:g} s), "
        f"{dispersed}" + (f"; {len(done)} already done in {out}, {len(pending)} to run" if done else ""))
    link, n_workers, run_seconds = None, 0, 0.0
    if pending:
        with _connected(client, workers, dashboard) as (dask_client, link):
            if link:
                say(f"Dask dashboard: {link}")
            elif client is None and dashboard:
                say("Dask dashboard: none (it needs bokeh: pip install 'soadyn[campaign]')")
            n_workers = _check_workers(dask_client, say)
            run_start = time.perf_counter()
            _execute(dask_client, spec, store, pending, chunk_size, n_workers, progress, on_batch)
            run_seconds = time.perf_counter() - run_start
    table = store.finish()
    failed = int(sum(1 for s in table["status"].to_pylist() if s != "ok"))
    seconds = time.perf_counter() - start
    rate = f" ({len(pending) / run_seconds:.1f} runs/s)" if pending and run_seconds > 0 else ""
    where = f"; results in {Path(out) / 'results.parquet'}" if out is not None else ""
    say(f"done: {table.num_rows} runs, {failed} failed; {len(pending)} computed now in {seconds:.1f} s{rate}{where}")
    return CampaignResult(table=table, out=Path(out) if out is not None else None, runs=spec.runs,
                          done_before=len(done), computed=len(pending), failed=failed, seconds=seconds,
                          run_seconds=run_seconds, workers=n_workers, dashboard_link=link,
                          trajectories=store.trajectories)


@contextlib.contextmanager
def _connected(client, workers, dashboard):
    """(Client, dashboard link or None); closes what it made."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as error:
        raise CampaignError(f"campaigns need dask.distributed (pip install 'soadyn[campaign]'): {error}") from None
    if client is not None and not isinstance(client, (str, os.PathLike)):
        yield client, _dashboard(client)
        return
    if client is not None:
        try:
            made = Client(os.fspath(client), timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as error:
            raise CampaignError(f"cannot reach the Dask scheduler at {client}: {' '.join(str(error).split())}") \
                from None
        try:
            yield made, _dashboard(made)
        finally:
            made.close()
        return
    n = workers or _cores()
    serve = dashboard and _has_bokeh()
    # The worker processes start with SIGINT ignored (inherited), so a Ctrl-C in a terminal, sent to
    # the whole process group, interrupts this process only, which then closes the cluster.
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main_thread else None
    try:
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=":0" if serve else None, silence_logs=logging.CRITICAL)
    finally:
        if main_thread:
            signal.signal(signal.SIGINT, previous)
    try:
        made = Client(cluster)
        try:
            yield made, made.dashboard_link if serve else None
        except KeyboardInterrupt:
            _silence_distributed_logs()  # for the rest of the process: the interrupted command is ending
            raise
        finally:
            with _quiet_distributed_logs():
                made.close()
    finally:
        with _quiet_distributed_logs():
            cluster.close()


def _distributed_loggers() -> list:
    """distributed's logger and every child logger it has made (a child with its own level ignores its parent's)."""
    names = [name for name in logging.root.manager.loggerDict if name.startswith("distributed.")]
    return [logging.getLogger("distributed"), *(logging.getLogger(name) for name in names)]


def _silence_distributed_logs() -> None:
    for logger in _distributed_loggers():
        logger.setLevel(logging.CRITICAL + 1)


@contextlib.contextmanager
def _quiet_distributed_logs():
    """distributed's loggers silenced while our own cluster shuts down: after a Ctrl-C its scheduler may log
    the comms it could not finish (with a traceback), which is its teardown, not a campaign error. Their
    levels come back afterwards, unless an interrupt silenced them for good."""
    loggers = _distributed_loggers()
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels):
            if level <= logging.CRITICAL:
                logger.setLevel(level)


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def _has_bokeh() -> bool:
    import importlib.util

    return importlib.util.find_spec("bokeh") is not None


def _dashboard(client) -> Optional[str]:
    try:
        services = client.scheduler_info().get("services", {})
    except Exception:  # noqa: BLE001 - the link is a convenience
        return None
    return client.dashboard_link if "dashboard" in services else None


def _versions() -> dict:
    """What must agree between this process and the workers for bit-identical runs."""
    versions = software()
    return {k: versions.get(k) for k in ("soadyn", "numpy", "joint_angle_kernel", "mass_matrix_kernel",
                                          "appendage_kernel")}


def _check_workers(client, say) -> int:
    """The number of workers now; CampaignError if one cannot import soadyn or has other versions."""
    try:
        found = client.run(_versions)
    except Exception as error:  # noqa: BLE001 - e.g. ModuleNotFoundError on a worker without soadyn
        raise CampaignError(f"the Dask workers cannot run soadyn campaigns: {type(error).__name__}: "
                            f"{' '.join(str(error).split())}") from None
    mine = _versions()
    for address, theirs in found.items():
        if theirs != mine:
            raise CampaignError(f"worker {address} has {_format(theirs)}, this process {_format(mine)}: runs "
                                f"would not be reproducible; install the same versions on every worker")
    if not found:
        say("the scheduler has no workers yet; waiting for some (Ctrl-C stops)")
    return len(found)


def _format(versions: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in versions.items())


def _execute(client, spec, store, pending, chunk_size, n_workers, progress, on_batch) -> None:
    from dask.distributed import as_completed

    size = chunk_size or max(1, min(MAX_CHUNK, math.ceil(len(pending) / (TASKS_PER_WORKER * max(1, n_workers)))))
    token = uuid.uuid4().hex[:8]
    futures = {}

    def submit(ids):
        # The spec (with its model-file text) goes with each task: a task depending on one copy of it
        # would be placed next to that copy (Dask's data locality), on one worker.
        future = client.submit(run_chunk, spec, ids, key=f"soadyn-campaign-runs-{ids[0]}-{len(ids)}-{token}")
        futures[future] = ids
        return future

    for k in range(0, len(pending), size):
        submit(pending[k:k + size])
    bar = progress_bar(total=len(pending), unit="run", desc=spec.name, disable=not progress)
    failed, start = 0, time.monotonic()
    completed = as_completed(list(futures))
    try:
        for future in completed:
            ids = futures.pop(future)
            try:
                outcomes = future.result()
            except Exception as error:  # noqa: BLE001 - a task lost (its worker died): split it, then record it
                if len(ids) > 1:
                    for i in ids:
                        completed.add(submit([i]))
                    continue
                outcomes = [failed_outcome(spec, ids[0], f"{type(error).__name__}: {' '.join(str(error).split())}")]
            future.release()
            store.add(outcomes)
            failed += sum(o.row["status"] != "ok" for o in outcomes)
            bar.update(len(outcomes))
            postfix = {"failed": failed}
            if isinstance(bar, PlainProgress) and bar.n:
                postfix["eta"] = f"{(time.monotonic() - start) / bar.n * (bar.total - bar.n):.0f}s"
            bar.set_postfix(postfix, refresh=False)
            if on_batch is not None:
                on_batch(outcomes)
    finally:
        bar.close()
        if futures:
            client.cancel(list(futures))
