"""Hostile model files, each drawn from one integer seed.

A case saves a valid model (a loop scene, a flexible beam, a chain with
springs, armature, prescribed flags, frames, visuals and metadata, or a small
random tree of fuzz.api_cases) and spoils its text: one to three mutations of
the JSON (a value replaced by a hostile one: a string where a number goes,
"NaN", 1e308, a huge integer, null, a list or object of the wrong shape; a
raw token JSON does not allow: NaN, Infinity, 1e400, 400 digits, a lone
surrogate escape; a key dropped, duplicated, renamed or unknown; a list item
dropped or duplicated; a value wrapped in a list; arrays or objects nested
up to 200,000 levels deep in place of a value), or a text-level spoiling
(truncated, random bytes inserted or replacing it, the whole file nested
deep, a byte-order mark, invalid UTF-8).

Property: load_model returns a Model whose parameters are all finite (its
own model-file text holds finite numbers only) and whose forward dynamics at
a random state are finite (or a DynamicsError naming a DOF), or raises
ModelFileError naming the file; nothing else: no other exception, no crash,
no hang. The quick test is tests/fuzz/test_model_file_fuzz.py; the long campaign
bench/fuzz_campaign.py (surface "model_file").
"""
from __future__ import annotations

import copy
import functools
import json

import numpy as np

import soadyn
from soadyn.model_file import model_to_json
from fuzz.api_cases import random_model
from fuzz.loaded_model import check_loaded_model, load_hostile

DEPTHS = (1, 10, 250, 257, 1000, 10_000, 200_000)
HOSTILE_VALUES = (None, True, False, 0, -1, 1e308, -1e308, 5e-324, 2 ** 63, 2 ** 64, -(2 ** 63) - 1, 10 ** 30,
                  "", "NaN", "nan", "inf", "1.5", "\u00e9\u2603", "world", [], {}, [1.0, 2.0], [[1.0]],
                  [0.0, 0.0, 0.0], {"a": 1}, [None, None, None])
RAW_TOKENS = ("NaN", "-Infinity", "Infinity", "1e400", "-1e400", "1" + "0" * 400, "01", "+1", ".5", "1.", "0x10",
              "tru", "nul", "'a'", '"\\ud800"', '"\\u0000"', '"a\\qb"', "1e-400")
UNKNOWN_KEYS = ("masss", "Mass", "", "zzz", "description", "__proto__")


def deep_text(rng: np.random.Generator) -> str:
    depth = int(rng.choice(DEPTHS))
    if rng.uniform() < 0.5:
        return "[" * depth + ("1" if rng.uniform() < 0.5 else "") + "]" * depth
    return '{"a": ' * depth + "1" + "}" * depth


def rich_model() -> soadyn.Model:
    """A chain with every kind of model-file item: springs, armature, prescribed flags, frames, visuals."""
    m = soadyn.scenes.pendulum_chain(3)
    m.add_joint_spring("spring", 0, stiffness=4.0, damping=0.3, rest=0.2)
    m.set_armature(1, 0.05)
    m.set_prescribed([m.dof_names[2]])
    m.add_point_spring("strut", m.body_names[1], None, stiffness=30.0, damping=0.5,
                       placement_b=np.array([0.0, 0.0, 1.0]), force_law=([0.2, 1.0, 3.0], [-5.0, 0.0, 60.0]))
    m.add_body("tip", m.body_names[-1], soadyn.Joint.fixed(), placement=np.array([0.0, 0.0, -0.5]))
    m.visuals = [soadyn.Visual("box", m.body_names[0], "box", size=[0.1, 0.2, 0.3]),
                 soadyn.Visual("tri", m.body_names[1], "mesh", vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                               faces=[[0, 1, 2]])]
    return m


BASES = 6  # four built models, two random trees


@functools.lru_cache(maxsize=None)
def base_text(which: int) -> str:
    """The model-file text of base model `which` (0-3; 4 and up: random trees)."""
    scenes = soadyn.scenes
    if which == 0:
        return model_to_json(scenes.four_bar(), metadata={"source": "four_bar", "runs": [1, 2], "nested": {"a": []}})
    if which == 1:
        return model_to_json(rich_model())
    if which == 2:
        return model_to_json(scenes.cantilever_beam(1.0, 2.0, 1.5, 2, n_nodes=4))
    if which == 3:
        return model_to_json(scenes.slider_crank())
    return model_to_json(random_model(np.random.default_rng(which)))


class _Raw:
    """Raw JSON text to splice in place of a value or a key once the document is dumped."""

    def __init__(self):
        self.texts: list[str] = []

    def __call__(self, text: str) -> str:
        self.texts.append(text)
        return f"@@raw-{len(self.texts) - 1}@@"

    def splice(self, dumped: str) -> str:
        for n, text in enumerate(self.texts):
            dumped = dumped.replace(f'"@@raw-{n}@@"', text)
        return dumped


def prepare() -> None:
    """Builds the base texts once, in the process that forks the cases, not in every child."""
    for which in range(BASES):
        base_text(which)


def locations(data) -> list:
    """(container, key) of every value in the document, containers included."""
    found, stack = [], [data]
    while stack:
        node = stack.pop()
        for key, value in (node.items() if isinstance(node, dict) else enumerate(node)):
            found.append((node, key))
            if isinstance(value, (dict, list)):
                stack.append(value)
    return found


def mutate_value(rng: np.random.Generator, data, raw: _Raw) -> None:
    """One structural mutation of the parsed document `data`, in place."""
    places = locations(data)
    if not places:
        return
    node, key = places[rng.integers(len(places))]
    action = rng.choice(["value", "value", "raw", "deep", "drop", "duplicate", "unknown", "rename", "wrap"])
    if action == "value":
        node[key] = copy.deepcopy(HOSTILE_VALUES[rng.integers(len(HOSTILE_VALUES))])
    elif action == "raw":
        node[key] = raw(str(rng.choice(RAW_TOKENS)))
    elif action == "deep":
        node[key] = raw(deep_text(rng))
    elif action == "drop":
        del node[key]
    elif action == "duplicate" and isinstance(node, list):
        node.insert(int(key), copy.deepcopy(node[key]))
    elif action == "duplicate":  # the same key twice in one object
        node[raw(json.dumps(key))] = copy.deepcopy(HOSTILE_VALUES[rng.integers(len(HOSTILE_VALUES))])
    elif action == "unknown" and isinstance(node, dict):
        node[str(rng.choice(UNKNOWN_KEYS))] = node[key]
    elif action == "rename" and isinstance(node, dict):
        node[key.upper() if key != key.upper() else key + "_"] = node.pop(key)
    elif action == "wrap":
        node[key] = [node[key]] if rng.uniform() < 0.5 else {"value": node[key]}


def spoil_text(rng: np.random.Generator, text: str) -> bytes:
    """One text-level spoiling of the model-file `text`."""
    data = text.encode()
    action = rng.choice(["truncate", "insert", "replace", "bytes", "wrap", "bom", "utf8"])
    at = int(rng.integers(len(data) + 1))
    junk = bytes(rng.integers(0, 256, int(rng.integers(1, 40)), dtype=np.uint8))
    if action == "truncate":
        return data[:at]
    if action == "insert":
        return data[:at] + junk + data[at:]
    if action == "replace":
        return data[:at] + junk + data[at + len(junk):]
    if action == "bytes":
        return junk * int(rng.integers(1, 20))
    if action == "wrap":
        depth = int(rng.choice(DEPTHS))
        return b"[" * depth + data + b"]" * depth
    if action == "bom":
        return b"\xef\xbb\xbf" + data
    return data[:at] + b"\xff\xfe" + data[at:]


def file_bytes(rng: np.random.Generator) -> bytes:
    text = base_text(int(rng.integers(BASES)))
    r = rng.uniform()
    if r < 0.1:
        return text.encode()
    if r < 0.3:
        return spoil_text(rng, text)
    data, raw = json.loads(text), _Raw()
    for _ in range(int(rng.integers(1, 4))):
        mutate_value(rng, data, raw)
    return raw.splice(json.dumps(data, indent=1)).encode("utf-8", "surrogatepass")


def run_case(seed: int) -> str:
    """'ok', 'ModelFileError' or 'DynamicsError'; AssertionError or another exception when the property fails."""
    rng = np.random.default_rng(seed)
    loaded = load_hostile(file_bytes(rng), "fuzz.json", soadyn.load_model, soadyn.ModelFileError)
    return loaded if isinstance(loaded, str) else check_loaded_model(loaded, seed)
