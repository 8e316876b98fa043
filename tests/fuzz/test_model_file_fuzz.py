"""The model-file reader on hostile files (cases in fuzz/model_file_cases.py), each case in a forked child
(support/forked.py) so that a crash or a hang is counted: load_model returns a model with finite parameters
or raises ModelFileError naming the file. The long campaign runs the same cases:
python bench/fuzz_campaign.py --surface model_file."""
from fuzz.model_file_cases import BASES, base_text, run_case
from support.forked import run_forked


def test_model_file_reader_survives_hostile_files():
    for which in range(BASES):  # built once here, not in every child
        base_text(which)
    outcomes = {seed: run_forked(run_case, seed, timeout=30) for seed in range(200)}
    failures = [f"seed {seed}: {outcome:.300}" for seed, outcome in outcomes.items()
                if outcome not in ("ok", "expected")]
    assert not failures, "reproduce with fuzz.model_file_cases.run_case(seed):\n" + "\n".join(failures)
    assert "ok" in outcomes.values() and "expected" in outcomes.values()
