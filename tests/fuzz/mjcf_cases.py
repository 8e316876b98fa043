"""Hostile MJCF files, each drawn from one integer seed.

A case takes one of a few small valid MJCF models (a hinge chain with
springs, dampers, armature and sites; a free body carrying a ball joint and a
multi-joint body; a four-bar closed by an equality connect and a weld; a
finger with disable flags and an inline mesh) and spoils it: one to three
mutations of its elements (an attribute replaced by garbage, NaN, inf,
1e308, the wrong number of components; an attribute or element dropped,
duplicated or renamed; an element wrapped in bodies or unknown elements
nested up to 100,000 levels deep), or random bytes, or a truncated file.

Property: load_mjcf returns a Model whose parameters are all finite and
whose forward dynamics at a random state are finite (or a DynamicsError
naming a DOF), or raises MjcfError naming the file; nothing else: no other
exception, no crash, no hang. The quick test is tests/fuzz/test_mjcf_fuzz.py; the
long campaign bench/fuzz_campaign.py (surface "mjcf").
"""
from __future__ import annotations

from xml.etree import ElementTree

import mujoco  # noqa: F401 - imported once by the parent, not by every forked case (load_mjcf imports it late)
import numpy as np

import soadyn
from soadyn.mjcf import MjcfError
from fuzz.loaded_model import check_loaded_model, load_hostile

BASES = (
    """<mujoco model="chain"><option gravity="0 0 -9.81"/>
      <default><joint damping="0.1" armature="0.01"/><geom type="capsule" size="0.05" mass="1"/></default>
      <worldbody><body name="l1" pos="0 0 1"><joint name="j1" type="hinge" axis="0 1 0" stiffness="2" springref="0.3"/>
        <geom fromto="0 0 0 0 0 -0.5"/><site name="s1" pos="0 0 -0.5"/>
        <body name="l2" pos="0 0 -0.5"><joint name="j2" type="hinge" axis="1 0 0" ref="0.2" range="-1 1"/>
          <geom fromto="0 0 0 0 0 -0.5"/>
          <body name="l3" pos="0 0 -0.5"><joint name="j3" type="slide" axis="0 0 1" damping="3"/>
            <geom type="box" size="0.1 0.1 0.1"/></body></body></body></worldbody>
      <actuator><motor joint="j1"/></actuator></mujoco>""",
    """<mujoco model="free"><worldbody>
      <body name="base" pos="0 0 1" quat="1 0 0 0.3"><freejoint name="root"/><geom type="sphere" size="0.2" mass="2"/>
        <body name="arm" pos="0.3 0 0"><joint name="ball" type="ball" damping="0.2"/>
          <geom type="ellipsoid" size="0.1 0.2 0.05" mass="0.5"/>
          <body name="hand" pos="0.2 0 0"><joint name="h1" axis="0 0 1" pos="0.05 0 0"/>
            <joint name="h2" axis="0 1 0"/><geom type="cylinder" size="0.05 0.1" mass="0.3"/>
          </body></body></body></worldbody></mujoco>""",
    """<mujoco model="four_bar"><worldbody>
      <body name="crank"><joint name="a" axis="0 0 1"/><geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01"/>
        <body name="coupler" pos="0.1 0 0"><joint name="b" axis="0 0 1"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.01"/></body></body>
      <body name="rocker" pos="0.25 0 0"><joint name="c" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0 0.3 0" size="0.01"/></body>
      <body name="loose" pos="1 0 0"><joint name="d" type="slide" axis="1 0 0"/>
        <geom type="box" size=".1 .1 .1"/></body>
      </worldbody>
      <equality><connect name="close" body1="coupler" body2="rocker" anchor="0.3 0 0"/>
        <weld name="glue" body1="loose" active="false"/></equality></mujoco>""",
    """<mujoco model="finger"><option timestep="0.01"><flag gravity="disable" contact="disable"/></option>
      <asset><mesh name="tetra" vertex="0 0 0 0.1 0 0 0 0.1 0 0 0 0.1"/></asset>
      <worldbody><body name="proximal" pos="0 0 0.6"><joint name="p" type="hinge" axis="0 -1 0" damping="0.05"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.17" size="0.03" mass="0.05"/>
          <body name="distal" pos="0 0 -0.18">
            <joint name="d" type="hinge" axis="0 -1 0" stiffness="0.1" damping="0.05"/>
            <geom type="capsule" fromto="0 0 0 0 0 -0.16" size="0.028" mass="0.04"/></body></body>
        <body name="spinner" pos="0.2 0 0.4"><joint name="hinge" type="hinge" axis="0 1 0" damping="0.5"/>
          <geom type="mesh" mesh="tetra" mass="0.1"/></body></worldbody></mujoco>""",
)
BAD_VALUES = ("nan", "inf", "-inf", "1e308", "-1e308", "1e999", "", "abc", "1 2", "1 2 3 4 5", "0 0 0", "0 0 0 0",
              "1e-320", "-1", "0", "0x10", "1,2,3", "  ", "\u00e9", "nan nan nan", "1e200 0 0", "true", "disable",
              "hinge", "free", "ball", "world", "crank")
TAGS = ("body", "joint", "geom", "site", "worldbody", "inertial", "foo", "freejoint", "include", "default", "option")
DEPTHS = (2, 50, 250, 300, 100_000)


def mutate(text: str, rng: np.random.Generator) -> str:
    """One to three mutations of a valid MJCF text (see the module docstring)."""
    root = ElementTree.fromstring(text)
    deep = []
    for _ in range(int(rng.integers(1, 4))):
        elements = list(root.iter())
        element = elements[rng.integers(len(elements))]
        action = rng.choice(["value", "value", "value", "drop_attribute", "drop", "duplicate", "rename", "deep"])
        keys = sorted(element.attrib)
        parent = next((p for p in root.iter() if any(child is element for child in p)), None)
        if action == "value" and keys:
            element.set(keys[rng.integers(len(keys))], BAD_VALUES[rng.integers(len(BAD_VALUES))])
        elif action == "drop_attribute" and keys:
            del element.attrib[keys[rng.integers(len(keys))]]
        elif action == "drop" and parent is not None:
            parent.remove(element)
        elif action == "duplicate" and parent is not None:
            parent.append(ElementTree.fromstring(ElementTree.tostring(element)))
        elif action == "rename":
            element.tag = TAGS[rng.integers(len(TAGS))]
        elif action == "deep":  # a marker element, replaced by the nesting once written
            tag = "body" if rng.uniform() < 0.5 else "x"
            depth = int(DEPTHS[rng.integers(len(DEPTHS))])
            element.append(ElementTree.Element(f"deep{len(deep)}"))
            deep.append(f"<{tag}>" * depth + f"</{tag}>" * depth)
    written = ElementTree.tostring(root, encoding="unicode")
    for n, nesting in enumerate(deep):
        written = written.replace(f"<deep{n} />", nesting)
    return written


def file_bytes(rng: np.random.Generator) -> bytes:
    text = BASES[rng.integers(len(BASES))]
    r = rng.uniform()
    if r < 0.05:
        return bytes(rng.integers(0, 256, int(rng.integers(0, 400)), dtype=np.uint8))
    if r < 0.1:
        return text.encode()[:int(rng.integers(len(text)))]
    if r < 0.15:
        return text.encode()
    return mutate(text, rng).encode("utf-8")


def run_case(seed: int) -> str:
    """'ok', 'MjcfError' or 'DynamicsError'; AssertionError or another exception when the property fails."""
    rng = np.random.default_rng(seed)
    data = file_bytes(rng)
    floating = [None, True, False][rng.integers(3)]
    loaded = load_hostile(data, "fuzz.xml", lambda path: soadyn.load_mjcf(path, floating_base=floating), MjcfError)
    return loaded if isinstance(loaded, str) else check_loaded_model(loaded, seed)
