"""MuJoCo models and matrices shared by the tests comparing soadyn with MuJoCo: the MJCF models
shipped with gymnasium's MuJoCo environments, a four-bar written in MJCF (a connect constraint
closing it), and MuJoCo's full mass matrix."""
from __future__ import annotations

import os

import mujoco
import numpy as np


def gymnasium_assets() -> str:
    import gymnasium

    return os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")


FOUR_BAR = """<mujoco><option gravity="0 0 -9.81"/><worldbody>
 <body name="crank"><joint name="crank" axis="0 1 0" damping="0.1" armature="0.02"/>
   <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" mass="1"/>
   <body name="coupler" pos="0.2 0 0"><joint name="coupler" axis="0 1 0"/>
     <geom type="capsule" fromto="0 0 0 0.3 0 0.25" size="0.02" mass="1.5"/></body></body>
 <body name="rocker" pos="0.45 0 0"><joint name="rocker" axis="0 1 0" stiffness="3" springref="0.2"/>
   <geom type="capsule" fromto="0 0 0 0.05 0 0.25" size="0.02" mass="0.8"/></body>
</worldbody><equality><connect name="pin" body1="coupler" body2="rocker" anchor="0.3 0 0.25"/></equality></mujoco>"""


def full_mass_matrix(model, data) -> np.ndarray:
    """MuJoCo's M column by column (mj_mulM; mj_fullM's signature changed within 3.x)."""
    M, column = np.zeros((model.nv, model.nv)), np.zeros(model.nv)
    for k in range(model.nv):
        unit = np.zeros(model.nv)
        unit[k] = 1.0
        mujoco.mj_mulM(model, data, column, unit)
        M[:, k] = column
    return M
