"""Monte Carlo campaigns on Dask: `soadyn.campaign.run(spec, client=None)` and `soadyn campaign`.

A spec (TOML, spec.py) names a scene or model file, the dispersions (model parameters, start
state, event times, sources; dispersions.py), the number of runs, the duration, integrator and
step, and the outputs kept per run (metrics.py; optionally decimated trajectories). Each run is
a pure function of (spec, run id) (simulate.py), so the same spec gives bit-identical results
whatever the number of workers, and a run replays by its id (replaying.py). Results go to Parquet
as batches finish (store.py): an interrupted campaign resumes without redoing finished runs.
execute.py runs the batches on a Dask cluster; reporting.py summarizes and plots a results directory.
"""
from .errors import CampaignError, ResultsDirectoryError, SpecError
from .execute import CampaignResult, run, run_one
from .metrics import METRICS, metric
from .replaying import Replay, format_replay, replay
from .reporting import Report, format_summary, report
from .simulate import RunOutcome
from .spec import EXAMPLES, Spec, load_spec

__all__ = ["run", "load_spec", "replay", "report", "run_one", "Spec", "CampaignResult", "RunOutcome", "Replay",
           "Report", "SpecError", "CampaignError", "ResultsDirectoryError", "METRICS", "metric", "EXAMPLES",
           "format_replay", "format_summary"]
