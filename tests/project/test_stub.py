"""The committed stub of the compiled module is the one pybind11-stubgen generates from it (never kept by hand)."""
import pytest

from support.stub import REGENERATE, STUB, generated_stub, stub_difference


def test_committed_stub_is_the_generated_one(tmp_path):
    difference = stub_difference(generated_stub(tmp_path), STUB.read_text())
    if difference:
        pytest.fail(f"python/soadyn/_soadyn.pyi is not the stub generated from the compiled module; regenerate it "
                    f"from the repository root with `{REGENERATE}`:\n{difference}", pytrace=False)
