"""The model-file reader on hostile files (cases in fuzz/model_file_cases.py), each case in a forked child
(support/forked.py) so that a crash or a hang is counted: load_model returns a model with finite parameters
or raises ModelFileError naming the file. The long campaign runs the same cases:
python bench/fuzz_campaign.py --surface model_file."""
from support.forked import run_forked_cases


def test_model_file_reader_survives_hostile_files(tmp_path):
    outcomes = run_forked_cases("fuzz.model_file_cases", range(200), tmp_path, timeout=30)
    failures = [f"seed {seed}: {outcome:.300}" for seed, outcome in outcomes.items()
                if outcome not in ("ok", "expected")]
    assert not failures, "reproduce with fuzz.model_file_cases.run_case(seed):\n" + "\n".join(failures)
    assert "ok" in outcomes.values() and "expected" in outcomes.values()
