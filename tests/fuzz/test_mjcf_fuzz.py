"""The MJCF loader on hostile files (cases in fuzz/mjcf_cases.py), each case in a forked child
(support/forked.py) so that a crash or a hang is counted: load_mjcf returns a model with finite parameters or
raises MjcfError naming the file. The long campaign runs the same cases:
python bench/fuzz_campaign.py --surface mjcf."""
from support.forked import run_forked_cases


def test_mjcf_loader_survives_hostile_files(tmp_path):
    outcomes = run_forked_cases("fuzz.mjcf_cases", range(150), tmp_path, timeout=30)
    failures = [f"seed {seed}: {outcome:.300}" for seed, outcome in outcomes.items()
                if outcome not in ("ok", "expected")]
    assert not failures, "reproduce with fuzz.mjcf_cases.run_case(seed):\n" + "\n".join(failures)
    assert "ok" in outcomes.values() and "expected" in outcomes.values()
