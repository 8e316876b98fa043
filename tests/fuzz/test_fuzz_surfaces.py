"""Hostile input on the loop, analysis and batch surfaces (cases in fuzz/loop_cases.py, fuzz/analysis_cases.py,
fuzz/batch_cases.py), each case in a forked child (support/forked.py): every case ends "ok" or with a documented
error, never a crash, a hang, a silent NaN or an unexpected exception. The long campaign runs the same cases:
python bench/fuzz_campaign.py --surface loops analysis batch."""
import os
import signal

import numpy as np
import pytest

from fuzz import analysis_cases, batch_cases, loop_cases
from support.forked import judged, run_forked, run_forked_cases

SURFACES = {"loops": loop_cases, "analysis": analysis_cases, "batch": batch_cases}
SEEDS = range(300)


@pytest.mark.parametrize("surface", sorted(SURFACES))
def test_surface_survives_hostile_input(surface, tmp_path):
    outcomes = run_forked_cases(SURFACES[surface].__name__, SEEDS, tmp_path)
    failures = [f"seed {seed}: {outcome:.300}" for seed, outcome in outcomes.items()
                if outcome not in ("ok", "expected")]
    assert not failures, f"{surface}: {len(failures)} of {len(SEEDS)} cases failed " \
                         f"(reproduce with {SURFACES[surface].__name__}.run_case(seed)):\n" + "\n".join(failures)
    assert "ok" in outcomes.values() and "expected" in outcomes.values()


def _returns(value):
    return lambda seed: judged(lambda: ("probe", value, {}))


def _raises(error):
    def run_case(seed):
        raise error
    return run_case


def _kills_itself(seed):
    os.kill(os.getpid(), signal.SIGSEGV)


def _hangs(seed):
    while True:
        signal.pause()


@pytest.mark.parametrize("run_case,outcome", [
    (_returns(np.ones(3)), "ok"),
    (lambda seed: judged(lambda: _raises(ValueError("q[0] is NaN"))(seed)), "expected"),
    (_returns(np.array([1.0, np.nan])), "non-finite: probe returned a non-finite result without raising"),
    (lambda seed: judged(lambda: ("probe", 1.0, {"q": np.ones(2) + 1j})),
     "non-finite: probe took q of dtype complex128 as numbers without raising"),
    (lambda seed: judged(lambda: _raises(TypeError("'float' object is not iterable"))(seed)),
     "non-finite: TypeError without a message naming the argument: TypeError(\"'float' object is not iterable\")"),
    (_raises(KeyError("b0")), "unexpected: KeyError: 'b0'"),
    (_kills_itself, f"crash: signal {int(signal.SIGSEGV)}"),
    (_hangs, "hang"),
], ids=["ok", "expected", "non-finite", "complex taken", "unnamed error", "unexpected", "crash", "hang"])
def test_the_forked_runner_reports_every_outcome(run_case, outcome):
    """The runner the surface tests rely on tells each outcome apart, so a failing case cannot pass unseen."""
    assert run_forked(run_case, 0, timeout=0.5 if outcome == "hang" else 10.0) == outcome


PROBE_CASES = """
import os
import signal

import numpy as np

from support.forked import judged


def run_case(seed):
    if seed == 1:
        os.kill(os.getpid(), signal.SIGSEGV)
    if seed == 2:
        while True:
            signal.pause()
    if seed == 3:
        raise KeyError("b0")
    if seed == 4:
        print('[4, "crash: a case printing this must not be read as its outcome"]', flush=True)
    return judged(lambda: ("probe", np.array([1.0, np.nan]) if seed == 5 else np.ones(3), {}))
"""


def test_the_case_server_reports_what_run_forked_reports(tmp_path):
    """run_forked_cases, which the surface tests use, forks each case from a small server process: every
    outcome reaches the test as run_forked in this process would give it, whatever the case prints."""
    (tmp_path / "probe_cases.py").write_text(PROBE_CASES)
    assert run_forked_cases("probe_cases", range(6), tmp_path, timeout=0.5) == {
        0: "ok", 1: f"crash: signal {int(signal.SIGSEGV)}", 2: "hang", 3: "unexpected: KeyError: 'b0'", 4: "ok",
        5: "non-finite: probe returned a non-finite result without raising"}
    seeds = range(12)
    assert run_forked_cases("fuzz.loop_cases", seeds, tmp_path) == {seed: run_forked(loop_cases.run_case, seed)
                                                                     for seed in seeds}
