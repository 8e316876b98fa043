"""soadyn.load_mjcf against MuJoCo itself.

Every MJCF model shipped with gymnasium's MuJoCo environments loads; at random states
MuJoCo's mass matrix (mj_mulM), bias forces (qfrc_bias) and spring and damper forces
(qfrc_spring + qfrc_damper) agree with soadyn's mass_matrix, inverse dynamics at zero
acceleration and force elements, through the velocity map qvel = T v (free joints:
world-frame linear velocity in MuJoCo, body-frame in soadyn), to 1e-9 relative. Sites
become frames at MuJoCo's site poses. Mechanisms written here with equality connect and
weld constraints agree with the KKT system assembled from MuJoCo's matrices and point
Jacobians (mj_jac, mj_jacDot). Hostile input gives MjcfError naming the file or item.
"""
from __future__ import annotations

import os
import warnings

import mujoco
import numpy as np
import pytest

import soadyn
from soadyn.check import rigid_part
from soadyn.mjcf import MjcfError, MjcfIgnoredWarning, load_mjcf_with_map
from test_loops_mujoco import full_mass_matrix

RTOL = 1e-9


def gymnasium_assets() -> str:
    import gymnasium

    return os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")


GYMNASIUM = sorted(f for f in os.listdir(gymnasium_assets()) if f.endswith(".xml"))


def load_quietly(source, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MjcfIgnoredWarning)
        return load_mjcf_with_map(source, **kwargs)


def random_qpos(mj, rng) -> np.ndarray:
    qpos = mj.qpos0.copy()
    for j in range(mj.njnt):
        a, kind = mj.jnt_qposadr[j], mj.jnt_type[j]
        if kind in (2, 3):
            qpos[a] += 0.5 * rng.normal()
        elif kind == 1:
            x = rng.normal(size=4)
            qpos[a:a + 4] = x / np.linalg.norm(x)
        else:
            qpos[a:a + 3] = rng.normal(size=3)
            x = rng.normal(size=4)
            qpos[a + 3:a + 7] = x / np.linalg.norm(x)
    return qpos


def relative(a, b) -> float:
    return float(np.abs(a - b).max(initial=0.0) / max(np.abs(b).max(initial=0.0), 1.0))


@pytest.mark.parametrize("name", GYMNASIUM)
def test_gymnasium_model_matches_mujoco(name):
    loaded = load_quietly(os.path.join(gymnasium_assets(), name))
    m, mj = loaded.model, loaded.mujoco_model
    assert m.nv == mj.nv and m.nq == mj.nq
    bare = rigid_part(m)
    data = mujoco.MjData(mj)
    rng = np.random.default_rng(len(name))
    zero = np.zeros(m.nv)
    for _ in range(4):
        qpos, qvel = random_qpos(mj, rng), rng.normal(size=mj.nv)
        data.qpos[:], data.qvel[:] = qpos, qvel
        mujoco.mj_forward(mj, data)
        q, v = loaded.soadyn_state(qpos, qvel)
        np.testing.assert_allclose(loaded.mujoco_state(q, v)[0], qpos, atol=1e-14)
        T = loaded.velocity_map(q)
        M = full_mass_matrix(mj, data)
        assert relative(soadyn.mass_matrix(m, q), T.T @ M @ T) < RTOL, "M"
        bias = T.T @ (data.qfrc_bias + M @ loaded.velocity_map_rate(q, v))
        assert relative(soadyn.inverse_dynamics(bare, q, v, zero), bias) < RTOL, "qfrc_bias"
        passive = soadyn.inverse_dynamics(bare, q, v, zero) - soadyn.inverse_dynamics(m, q, v, zero)
        assert relative(passive, T.T @ (data.qfrc_spring + data.qfrc_damper)) < RTOL, "qfrc_spring + qfrc_damper"
        for s in range(mj.nsite):  # sites are frames at MuJoCo's site poses
            site = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_SITE, s)
            if site in m.frame_names:
                pose = soadyn.frame_pose(m, q, site)
                np.testing.assert_allclose(pose[:3, 3], data.site_xpos[s], atol=1e-12)
                np.testing.assert_allclose(pose[:3, :3], data.site_xmat[s].reshape(3, 3), atol=1e-12)


def test_gymnasium_models_name_dofs_after_mujoco_joints_and_report_what_is_ignored():
    path = os.path.join(gymnasium_assets(), "ant.xml")
    with pytest.warns(MjcfIgnoredWarning) as record:
        loaded = load_mjcf_with_map(path)
    assert len(record) == 1  # once per load
    message = str(record[0].message)
    assert "ant.xml" in message and "8 actuators (actuator0:hip_4" in message and "contacts" in message
    assert "joint limits" in message and "hip_1" in message
    mj, m = loaded.mujoco_model, loaded.model
    joint_names = [mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(1, mj.njnt)]
    assert [n for n in m.dof_names if not n.startswith("root")] == joint_names
    assert np.count_nonzero(m.armature) == 8  # the legs' armature="1", the free root's 0
    assert len(m.visuals) == mj.ngeom


def test_floating_base_options():
    xml = """<mujoco><worldbody><body name="a" pos="0 0 1"><geom type="sphere" size="0.1" mass="1"/>
             <body name="b" pos="0 0 -0.3"><joint name="j" axis="0 1 0"/><geom type="sphere" size="0.05" mass="0.5"/>
             </body></body><body name="c" pos="1 0 0"><freejoint name="c_free"/><geom type="box" size=".1 .1 .1" mass="2"/>
             </body></worldbody></mujoco>"""
    fixed = load_quietly(xml).model
    assert fixed.dof_names[:1] == ["j"] and fixed.nv == 7
    floating = load_quietly(xml, floating_base=True).model
    assert floating.nv == 13 and "a:root:wx" in floating.dof_names
    welded = load_quietly(xml, floating_base=False).model
    assert welded.nv == 1
    with pytest.raises(TypeError, match="floating_base"):
        load_mjcf_with_map(xml, floating_base="yes")


# --- equality constraints: loops against MuJoCo's KKT system -------------------------------------

FOUR_BAR = """<mujoco><option gravity="0 0 -9.81"/><worldbody>
 <body name="crank"><joint name="crank" axis="0 1 0" damping="0.1" armature="0.02"/>
   <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" mass="1"/>
   <body name="coupler" pos="0.2 0 0"><joint name="coupler" axis="0 1 0"/>
     <geom type="capsule" fromto="0 0 0 0.3 0 0.25" size="0.02" mass="1.5"/></body></body>
 <body name="rocker" pos="0.45 0 0"><joint name="rocker" axis="0 1 0" stiffness="3" springref="0.2"/>
   <geom type="capsule" fromto="0 0 0 0.05 0 0.25" size="0.02" mass="0.8"/></body>
</worldbody><equality><connect name="pin" body1="coupler" body2="rocker" anchor="0.3 0 0.25"/></equality></mujoco>"""

SLIDER_CRANK = """<mujoco><option gravity="0 -9.81 0"/><worldbody>
 <body name="crank"><joint name="crank" axis="0 0 1"/>
   <geom type="box" pos="0.05 0 0" size="0.05 0.01 0.01" mass="0.5"/>
   <body name="rod" pos="0.1 0 0" euler="0 0 -20" ><joint name="rod" axis="0 0 1"/>
     <geom type="box" pos="0.15 0 0" size="0.15 0.01 0.01" mass="0.7"/></body></body>
 <body name="slider" pos="0.3819 0 0"><joint name="slide" type="slide" axis="1 0 0"/>
   <geom type="box" size="0.03 0.03 0.03" mass="1.2"/></body>
</worldbody><equality><connect name="wrist" body1="rod" body2="slider" anchor="0.3 0 0"/></equality></mujoco>"""

SPATIAL = """<mujoco><option gravity="0.5 -1 -9.81"/><worldbody>
 <body name="a1" pos="0 0 0.5"><joint name="a1" axis="0 0 1" ref="0.3"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="1"/>
   <body name="a2" pos="0.3 0 0"><joint name="a2" axis="0 1 0" pos="0.01 0 0"/><joint name="a2b" axis="1 0 0"/>
     <geom type="capsule" fromto="0 0 0 0.3 0 -0.2" size="0.02" mass="0.6"/>
     <body name="a3" pos="0.3 0 -0.2"><joint name="a3" type="ball"/><geom type="sphere" pos="0.05 0 0" size="0.04" mass="0.4"/></body>
   </body></body>
 <body name="b1" pos="0.8 0.1 0.5"><joint name="b1" axis="0 0 1"/><geom type="capsule" fromto="0 0 0 -0.2 0 0" size="0.02" mass="0.9"/>
   <body name="b2" pos="-0.2 0 0"><joint name="b2" axis="0 1 0"/><joint name="b2s" type="slide" axis="1 0 0"/>
     <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.5"/></body></body>
</worldbody><equality><weld name="tie" body1="a3" body2="b2"/></equality></mujoco>"""

MECHANISMS = {"four-bar": FOUR_BAR, "slider-crank": SLIDER_CRANK, "spatial-weld": SPATIAL}


def point_jacobians(mj, data, body: int, point_world):
    jp, jr = np.zeros((3, mj.nv)), np.zeros((3, mj.nv))
    djp, djr = np.zeros((3, mj.nv)), np.zeros((3, mj.nv))
    mujoco.mj_jac(mj, data, jp, jr, point_world, body)
    mujoco.mj_jacDot(mj, data, djp, djr, point_world, body)
    return jp, jr, djp, djr


def mujoco_kkt_accelerations(mj, data, tau) -> np.ndarray:
    """qacc of M qacc + bias = tau + J' lambda, J qacc = -Jdot qvel, every active connect or weld
    written from the two bodies' point Jacobians (MuJoCo's own), minimum-norm multipliers."""
    rows, rates = [], []
    for e in range(mj.neq):
        if not data.eq_active[e]:
            continue
        b1, b2 = mj.eq_obj1id[e], mj.eq_obj2id[e]
        d = mj.eq_data[e]
        if mj.eq_type[e] == 0:  # connect: the anchors of body 1 and body 2 coincide
            p1 = data.xpos[b1] + data.xmat[b1].reshape(3, 3) @ d[0:3]
            p2 = data.xpos[b2] + data.xmat[b2].reshape(3, 3) @ d[3:6]
            j1, _, dj1, _ = point_jacobians(mj, data, b1, p1)
            j2, _, dj2, _ = point_jacobians(mj, data, b2, p2)
            rows.append(j1 - j2)
            rates.append((dj1 - dj2) @ data.qvel)
        else:  # weld: relative angular velocity and the anchor's relative velocity vanish
            p = data.xpos[b2] + data.xmat[b2].reshape(3, 3) @ d[0:3]
            j1, r1, dj1, dr1 = point_jacobians(mj, data, b1, p)
            j2, r2, dj2, dr2 = point_jacobians(mj, data, b2, p)
            rows.append(np.vstack([r1 - r2, j1 - j2]))
            rates.append(np.concatenate([(dr1 - dr2) @ data.qvel, (dj1 - dj2) @ data.qvel]))
    J, rate = np.vstack(rows), np.concatenate(rates)
    M = full_mass_matrix(mj, data)
    n, k = mj.nv, J.shape[0]
    K = np.block([[M, -J.T], [J, np.zeros((k, k))]])
    rhs = np.concatenate([tau + data.qfrc_spring + data.qfrc_damper - data.qfrc_bias, -rate])
    return np.linalg.lstsq(K, rhs, rcond=None)[0][:n]


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_equality_loops_match_mujoco_kkt(name):
    loaded = load_quietly(MECHANISMS[name])
    m, mj = loaded.model, loaded.mujoco_model
    assert m.nloops == mj.neq == 1
    q0, _ = loaded.soadyn_state(mj.qpos0, np.zeros(mj.nv))
    assert np.abs(soadyn.loop_residual(m, q0)).max() < 1e-4  # the file's pose closes the loop (to its digits)
    data = mujoco.MjData(mj)
    rng = np.random.default_rng(3)
    for _ in range(3):
        q = soadyn.assemble(m, soadyn.integrate(m, q0, 0.2 * rng.normal(size=m.nv), 1.0))
        v = soadyn.project_velocity(m, q, rng.normal(size=m.nv))
        tau = rng.normal(size=m.nv)
        qpos, qvel = loaded.mujoco_state(q, v)
        data.qpos[:], data.qvel[:] = qpos, qvel
        mujoco.mj_forward(mj, data)
        T = loaded.velocity_map(q)  # identity here: no free joint
        qacc = mujoco_kkt_accelerations(mj, data, T @ tau)
        qdd = soadyn.constrained_dynamics(m, q, v, tau)[0]
        assert relative(T @ qdd, qacc) < RTOL, name


def test_weld_relpose_and_inactive_equalities():
    xml = FOUR_BAR.replace("</equality>", '<weld name="lock" body1="crank" body2="rocker" active="false"/>'
                                          '<joint name="couple" joint1="crank" joint2="rocker"/></equality>')
    with pytest.warns(MjcfIgnoredWarning, match="inactive equality constraints \\(lock\\).*other than connect "
                                                "and weld between bodies \\(couple\\)"):
        m = load_mjcf_with_map(xml).model
    assert m.loop_names == ["pin"]


# --- hostile input -----------------------------------------------------------------------------

def test_missing_file_and_malformed_xml_are_named(tmp_path):
    with pytest.raises(MjcfError, match="MJCF file '.*nowhere.xml' does not exist"):
        soadyn.load_mjcf(tmp_path / "nowhere.xml")
    with pytest.raises(MjcfError, match="MJCF string: MuJoCo cannot compile it"):
        soadyn.load_mjcf("<mujoco><worldbody><body name='a'><joint type='hinge'/></worldbody></mujoco>")
    bad = tmp_path / "bad.xml"
    bad.write_text("<mujoco><worldbody><body name='a'><geom type='sphere' size='-1'/></body></worldbody></mujoco>")
    with pytest.raises(MjcfError, match="bad.xml"):
        soadyn.load_mjcf(bad)
    truncated = tmp_path / "truncated.xml"
    truncated.write_text(open(os.path.join(gymnasium_assets(), "ant.xml")).read()[:500])
    with pytest.raises(MjcfError, match="truncated.xml"):
        soadyn.load_mjcf(truncated)


def test_a_massless_leaf_is_refused_by_mujoco_or_named():
    xml = """<mujoco><worldbody><body name="a"><joint name="j" axis="0 0 1"/></body></worldbody></mujoco>"""
    with pytest.raises(MjcfError, match="MJCF string"):
        soadyn.load_mjcf(xml)
