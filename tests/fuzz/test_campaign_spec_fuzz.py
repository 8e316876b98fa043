"""The quick run of the campaign-spec fuzzer (cases in fuzz/spec_cases.py; the long one is
bench/fuzz_campaign.py --surface spec): each hostile spec file is loaded in a forked child, so a
crash or a hang counts as a failure, and every case must give a Spec or a SpecError naming the
file and each problem's item."""
import collections

from support.forked import run_forked_cases

SEEDS = range(200)
HANG_SECONDS = 30.0  # one load takes milliseconds: only a case that never ends reaches this


def test_hostile_specs_give_a_spec_or_a_spec_error_naming_every_item(tmp_path):
    outcomes = run_forked_cases("fuzz.spec_cases", SEEDS, tmp_path, HANG_SECONDS)
    failures = {seed: outcome for seed, outcome in outcomes.items() if outcome not in ("ok", "expected")}
    assert not failures, f"run_case(seed) reproduces each: {dict(list(failures.items())[:5])}"
    counts = collections.Counter(outcomes.values())
    assert counts["ok"] >= 10 and counts["expected"] >= 100  # the cases reach both outcomes
