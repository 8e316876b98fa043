"""Hostile input on the loop, analysis and batch surfaces (cases in fuzz/loop_cases.py, fuzz/analysis_cases.py,
fuzz/batch_cases.py), each case in a forked child (support/forked.py): every case ends "ok" or with a documented
error, never a crash, a hang, a silent NaN or an unexpected exception. The long campaign runs the same cases:
python bench/fuzz_campaign.py --surface loops analysis batch."""
import os
import signal

import numpy as np
import pytest

from fuzz import analysis_cases, batch_cases, loop_cases
from support.forked import judged, run_forked

SURFACES = {"loops": loop_cases, "analysis": analysis_cases, "batch": batch_cases}
SEEDS = range(300)


@pytest.mark.parametrize("surface", sorted(SURFACES))
def test_surface_survives_hostile_input(surface):
    outcomes = {seed: run_forked(SURFACES[surface].run_case, seed) for seed in SEEDS}
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
