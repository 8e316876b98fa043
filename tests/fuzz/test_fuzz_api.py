"""Property test of the public API on hostile input (cases in fuzz/api_cases.py):
every call returns finite numbers or raises a documented error with a message."""
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fuzz.api_cases import run_case


@settings(max_examples=1500, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(min_value=0, max_value=2 ** 63 - 1))
def test_api_survives_hostile_input(seed):
    assert run_case(seed) in ("ok", "ValueError", "TypeError", "DynamicsError")
