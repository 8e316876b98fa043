"""Hostile URDF files, each drawn from one integer seed, for the long fuzz
campaign (bench/fuzz_campaign.py); tests/fuzz/test_urdf_fuzz.py holds the quick
property tests of the same kinds of files.

A case is random bytes, random URDF-like text, or a random valid tree with
up to three mutations (a value replaced by NaN, inf, 1e308, garbage or the
wrong number of components; an attribute or element dropped, duplicated or
renamed). Property: load_urdf returns a Model whose masses are finite and
whose forward dynamics at a random state are finite (or a DynamicsError
naming a DOF), or raises UrdfError naming the file; nothing else.
"""
from __future__ import annotations

import math
import os
import tempfile
import warnings
from typing import Any, Callable, Sequence
from xml.etree import ElementTree

import numpy as np

import soadyn
from fuzz.loaded_model import check_loaded_model

BAD_VALUES = ["nan", "inf", "-inf", "1e308", "-1e308", "1e999", "", "abc", "1 2", "1 2 3 4", "0 0 0", "1e-320",
              "-1", "0x10", "1,2,3", "  ", "\u00e9", "1e200 0 0", "0 1e200 0"]
URDF_CHARACTERS = list("<>/=\"' robotlinkjointnameparentchild0123456789.-e")


def vector(rng: np.random.Generator) -> str:
    return " ".join(repr(float(x)) for x in rng.uniform(-1, 1, 3))


def inertial(rng: np.random.Generator) -> str:
    if rng.uniform() < 0.05:
        return ""
    a, b = (float(x) for x in rng.uniform(0.01, 1.0, 2))
    c = float(rng.uniform(abs(a - b), a + b))
    return (f"<inertial><origin xyz='{vector(rng)}' rpy='{vector(rng)}'/><mass value='{float(rng.uniform(0.1, 10))!r}'/>"
            f"<inertia ixx='{a!r}' iyy='{b!r}' izz='{c!r}' ixy='0' ixz='0' iyz='0'/></inertial>")


def tree(rng: np.random.Generator) -> str:
    n = int(rng.integers(1, 8))
    parts = [f"<link name='l{k}'>{inertial(rng)}</link>" for k in range(n + 1)]
    for k in range(1, n + 1):
        kind = ["revolute", "continuous", "prismatic", "fixed", "floating", "planar"][rng.integers(6)]
        parts.append(f"<joint name='j{k}' type='{kind}'><parent link='l{rng.integers(k)}'/><child link='l{k}'/>"
                     f"<origin xyz='{vector(rng)}' rpy='{vector(rng)}'/><axis xyz='{vector(rng)}'/>"
                     f"<limit lower='-3' upper='3' effort='1' velocity='1'/></joint>")
    rng.shuffle(parts)
    return "<robot name='fuzz'>" + "".join(parts) + "</robot>"


def mutate(text: str, pick: Callable[[Sequence], Any]) -> str:
    """One to three mutations of a valid file; `pick` chooses an item of a
    sequence (from a seeded generator here, from hypothesis in
    tests/fuzz/test_urdf_fuzz.py)."""
    root = ElementTree.fromstring(text)
    for _ in range(pick([1, 2, 3])):
        element = pick(list(root.iter()))
        action = pick(["value", "value", "drop_attribute", "drop", "duplicate", "rename"])
        keys = sorted(element.attrib)
        if action == "value" and keys:
            element.set(pick(keys), pick(BAD_VALUES))
        elif action == "drop_attribute" and keys:
            del element.attrib[pick(keys)]
        elif action in ("drop", "duplicate") and element is not root:
            parent = next(p for p in root.iter() if any(child is element for child in p))
            if action == "drop":
                parent.remove(element)
            else:
                parent.append(ElementTree.fromstring(ElementTree.tostring(element)))
        elif action == "rename":
            element.tag = pick(["foo", "link", "joint", "robot", "inertial", "origin"])
    return ElementTree.tostring(root, encoding="unicode")


def file_bytes(rng: np.random.Generator) -> bytes:
    r = rng.uniform()
    if r < 0.1:
        return bytes(rng.integers(0, 256, int(rng.integers(0, 400)), dtype=np.uint8))
    if r < 0.2:
        return "".join(rng.choice(URDF_CHARACTERS, int(rng.integers(0, 300)))).encode()
    text = tree(rng)
    pick = lambda items: items[rng.integers(len(items))]  # noqa: E731
    return (mutate(text, pick) if rng.uniform() < 0.6 else text).encode("utf-8", "surrogatepass")


def run_case(seed: int) -> str:
    rng = np.random.default_rng(seed)
    data = file_bytes(rng)
    floating = bool(rng.uniform() < 0.5)
    policy = ["strict", "repair", "accept"][rng.integers(3)]
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "fuzz.urdf")
        with open(path, "wb") as f:
            f.write(data)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                model = soadyn.load_urdf(path, floating_base=floating, inertia=policy)
        except soadyn.UrdfError as error:
            if path not in str(error):
                raise AssertionError(f"UrdfError does not name the file: {error}") from error
            return "UrdfError"
    if not all(math.isfinite(m) and m >= 0 for m in model.masses):
        raise AssertionError("a loaded model has a non-finite or negative mass")
    return check_loaded_model(model, seed)  # massless subtrees under "accept", singular inertias: DynamicsError
