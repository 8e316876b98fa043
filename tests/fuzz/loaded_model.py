"""Loading a hostile file (fuzz.model_file_cases, fuzz.mjcf_cases) and the property a loaded model keeps:
the loader's error names the file; a model's parameters are all finite, and its forward dynamics at a
random state are finite or a DynamicsError naming a DOF."""
from __future__ import annotations

import json
import math
import os
import tempfile
import warnings

import numpy as np

import soadyn
from soadyn.model_file import model_to_json


def load_hostile(data: bytes, file_name: str, load, error: type):
    """load(path) of `data` written to a temporary file: the model, or the name of `error` when load raised
    it naming the file (warnings silenced); AssertionError when the error does not name the file."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, file_name)
        with open(path, "wb") as f:
            f.write(data)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return load(path)
        except error as exc:
            if path not in str(exc):
                raise AssertionError(f"{type(exc).__name__} does not name the file: {exc}") from exc
            return type(exc).__name__


def check_finite_parameters(model: soadyn.Model) -> None:
    """Every number of the model's own model-file text is finite (a non-finite one would be written null)."""
    stack = [json.loads(model_to_json(model))]
    while stack:
        node = stack.pop()
        for value in (node.values() if isinstance(node, dict) else node):
            if isinstance(value, (dict, list)):
                stack.append(value)
            elif value is None or isinstance(value, float) and not math.isfinite(value):
                raise AssertionError(f"a loaded model holds a non-finite parameter ({value!r})")


def check_loaded_model(model: soadyn.Model, seed: int) -> str:
    """'ok' or 'DynamicsError' (see the module docstring); AssertionError when the property fails."""
    check_finite_parameters(model)
    rng = np.random.default_rng(seed)
    q = soadyn.random_configuration(model, seed)
    v, tau = rng.normal(size=(2, model.nv))
    try:
        qdd = soadyn.forward_dynamics(model, q, v, tau)
    except soadyn.DynamicsError as error:
        if "DOF '" not in str(error):
            raise AssertionError(f"DynamicsError without a DOF: {error}") from error
        return "DynamicsError"
    if not np.all(np.isfinite(qdd)):
        raise AssertionError("forward dynamics of a loaded model returned non-finite values")
    return "ok"
