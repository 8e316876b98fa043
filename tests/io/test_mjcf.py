"""soadyn.load_mjcf against MuJoCo itself.

Every MJCF model shipped with gymnasium's MuJoCo environments loads; at random states
MuJoCo's mass matrix (mj_mulM), bias forces (qfrc_bias) and spring and damper forces
(qfrc_spring + qfrc_damper) agree with soadyn's mass_matrix, inverse dynamics at zero
acceleration and force elements, through the velocity map qvel = T v (free joints:
world-frame linear velocity in MuJoCo, body-frame in soadyn), to 1e-9 relative. Sites
become frames at MuJoCo's site poses. Mechanisms written here with equality connect and
weld constraints agree with the KKT system assembled from MuJoCo's matrices and point
Jacobians (mj_jac, mj_jacDot). <option><flag> disable flags: a finger like dm_control's
(gravity disabled) and its variants with springs and dampers disabled agree with MuJoCo
with the same flags. Hostile input gives MjcfError naming the file or item.
"""
from __future__ import annotations

import itertools
import os
import warnings

import mujoco
import numpy as np
import pytest

import soadyn
from soadyn.bounded_input import MAX_NESTING_DEPTH
from soadyn.check import rigid_part
from soadyn.mjcf import MjcfError, MjcfIgnoredWarning, load_mjcf_with_map
from support.mujoco_models import FOUR_BAR, full_mass_matrix, gymnasium_assets

RTOL = 1e-9
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


# --- <option><flag> disable flags ------------------------------------------------------------------

# dm_control's finger, as its suite writes it in essence: gravity disabled, damped hinges; here with springs too
# (a `ref` and a `springref`) so that every honoured flag changes the forces.
FINGER = """<mujoco model="finger"><compiler angle="degree"/><option timestep="0.01"><flag {flags}/></option>
  <default><joint type="hinge" axis="0 -1 0" damping="0.05" stiffness="0.3" springref="20"/>
    <geom type="capsule" size="0.03"/></default>
  <worldbody>
    <body name="proximal" pos="-0.2 0 0.4"><joint name="proximal" range="-110 110" ref="-90"/>
      <geom name="proximal" fromto="0 0 0 0 0 -0.17" mass="0.05"/>
      <body name="distal" pos="0 0 -0.18"><joint name="distal" range="-110 110"/>
        <geom name="distal" fromto="0 0 0 0 0 -0.16" size="0.028" mass="0.04"/>
        <site name="touchtop" pos="0 0 -0.16"/></body></body>
    <body name="spinner" pos="0.2 0 0.4"><joint name="hinge" damping="0.5" stiffness="0"/>
      <geom name="cap" fromto="0.1 0 0 -0.1 0 0" size="0.02" mass="0.1"/>
      <geom name="tip" type="sphere" pos="0.1 0 0" size="0.03" mass="0.02"/></body>
  </worldbody>
  <actuator><motor name="proximal" joint="proximal" gear="1"/><motor name="distal" joint="distal" gear="1"/></actuator>
</mujoco>"""


def mujoco_joint_forces(mj, qpos, qvel) -> np.ndarray:
    """qfrc_bias - qfrc_passive: what inverse dynamics at zero acceleration gives with springs and dampers."""
    data = mujoco.MjData(mj)
    data.qpos[:], data.qvel[:] = qpos, qvel
    mujoco.mj_forward(mj, data)
    return data.qfrc_bias - data.qfrc_passive


@pytest.mark.parametrize("disabled", [("gravity",), ("spring",), ("damper",), ("spring", "damper"),
                                      ("gravity", "spring", "damper")])
def test_disable_flags_are_honoured_like_mujoco(disabled):
    """dm_control's finger disables gravity: the model must have none, and a disabled spring or damper no
    stiffness or damping; bias and passive forces then agree with MuJoCo's with the same flags, and differ
    from the model without them."""
    flags = " ".join(f'{flag}="disable"' for flag in disabled)
    loaded = load_quietly(FINGER.format(flags=flags))
    m, mj = loaded.model, loaded.mujoco_model
    enabled = load_quietly(FINGER.format(flags="")).mujoco_model
    assert np.array_equal(m.gravity, np.zeros(3)) == ("gravity" in disabled)
    for element in soadyn.force_elements(m):
        if "spring" in disabled:
            assert element["stiffness"] == 0
        if "damper" in disabled:
            assert element["damping"] == 0
    rng = np.random.default_rng(11)
    for _ in range(4):
        qpos, qvel = random_qpos(mj, rng), rng.normal(size=mj.nv)
        q, v = loaded.soadyn_state(qpos, qvel)
        expected = mujoco_joint_forces(mj, qpos, qvel)
        assert relative(soadyn.inverse_dynamics(m, q, v, np.zeros(m.nv)), expected) < RTOL
        assert relative(mujoco_joint_forces(enabled, qpos, qvel), expected) > 1e-3  # the flags matter here


@pytest.mark.parametrize("flag", ["equality", "constraint"])
def test_disabled_equalities_make_no_loops(flag):
    """MuJoCo enforces no equality when equality or constraint is disabled: nor does the model."""
    assert load_quietly(FOUR_BAR).model.nloops == 1
    disabled = FOUR_BAR.replace("<worldbody>", f'<option><flag {flag}="disable"/></option><worldbody>', 1)
    assert load_quietly(disabled).model.nloops == 0


def test_other_disable_flags_are_reported_with_the_ignored_features():
    xml = FINGER.format(flags='gravity="disable" contact="disable" warmstart="disable" limit="disable"')
    with pytest.warns(MjcfIgnoredWarning) as record:
        soadyn.load_mjcf(xml)
    (message,) = [str(w.message) for w in record]
    assert "3 disable flags without a soadyn counterpart (contact, limit, warmstart)" in message
    assert "gravity" not in message and "2 actuators (proximal, distal)" in message


# --- bounds ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("nesting", ["<x>", "<body>"])
def test_xml_nested_deeper_than_the_bound_is_refused_naming_the_limit(nesting, tmp_path):
    """100,000 nested elements: refused by name and limit before MuJoCo reads the file (its own parser stops
    near 500 levels with a message that names no limit); 250 nested bodies still load."""
    close = nesting.replace("<", "</")
    path = tmp_path / "deep.xml"
    path.write_text(f"<mujoco><worldbody>{nesting * 100_000}{close * 100_000}</worldbody></mujoco>")
    with pytest.raises(MjcfError, match=f"nested more than {MAX_NESTING_DEPTH} elements deep") as error:
        soadyn.load_mjcf(path)
    assert str(path) in str(error.value)
    with pytest.raises(MjcfError, match=f"MJCF string: <x> is nested more than {MAX_NESTING_DEPTH}"):
        soadyn.load_mjcf("<mujoco>" + "<x>" * MAX_NESTING_DEPTH + "</x>" * MAX_NESTING_DEPTH + "</mujoco>")
    chain = "<body><geom size='0.1'/><joint/>" * 250 + "</body>" * 250
    assert load_quietly(f"<mujoco><worldbody>{chain}</worldbody></mujoco>").model.nv == 250


# --- effort limits from actuators --------------------------------------------------------------------

# One joint per case: a motor (gear 50, ctrlrange -1 1), a position servo with forcerange -3 2, one without
# limits, two motors on a slide (one reversed, ctrl- and force-limited), a motor on a ball joint, a motor under
# the joint's actuatorfrcrange, an actuatorfrcrange without actuator, and a joint pulled only through a tendon.
ACTUATED = """<mujoco><option><flag {flags}/></option><worldbody>
 <body name="a"><joint name="motor" axis="0 1 0"/><geom size="0.1" mass="1"/>
  <body name="b" pos="0 0 -0.3"><joint name="servo" axis="0 1 0"/><geom size="0.1" mass="1"/>
   <body name="c" pos="0 0 -0.3"><joint name="unlimited" axis="0 1 0"/><geom size="0.1" mass="1"/>
    <body name="d" pos="0 0 -0.3"><joint name="slide" type="slide" axis="1 0 0"/><geom size="0.1" mass="1"/>
     <body name="e" pos="0 0 -0.3"><joint name="ball" type="ball"/><geom size="0.1" mass="1"/>
      <body name="f" pos="0 0 -0.3"><joint name="clamped" axis="1 0 0" actuatorfrcrange="-20 20"/>
       <joint name="frc_only" axis="0 1 0" actuatorfrcrange="-0.5 0.7"/><joint name="tendon_only" axis="0 0 1"/>
       <geom size="0.1" mass="1"/>
 </body></body></body></body></body></body></worldbody>
 <tendon><fixed name="pull"><joint joint="tendon_only" coef="1"/></fixed></tendon>
 <actuator>
  <motor name="motor" joint="motor" gear="50" ctrlrange="-1 1"/>
  <position name="servo" joint="servo" kp="10" forcerange="-3 2"/>
  <position name="unlimited" joint="unlimited" kp="10"/>
  <motor name="slide_a" joint="slide" gear="2" ctrlrange="-1 1"/>
  <motor name="slide_b" joint="slide" gear="-1.5" ctrlrange="-0.5 2" forcerange="-1 1"/>
  <motor name="ball" joint="ball" gear="1 -2 3" ctrlrange="-1 1"/>
  <motor name="clamped" joint="clamped" gear="50" ctrlrange="-1 1"/>
  <motor name="pull" tendon="pull" ctrlrange="-1 1"/>
 </actuator></mujoco>"""

INF = np.inf
EFFORT_LIMITS = {  # slide: motors in [-2, 2] and -1.5 * [-0.5, 1] (ctrl clamped, then force): [-3.5, 2.75]
    "": {"motor": 50.0, "servo": 3.0, "unlimited": INF, "slide": 3.5, "ball:wx": 1.0, "ball:wy": 2.0,
         "ball:wz": 3.0, "clamped": 20.0, "frc_only": 0.7, "tendon_only": INF},
    # MuJoCo no longer clamps ctrl: only forcerange and actuatorfrcrange bound the forces
    'clampctrl="disable"': {"motor": INF, "servo": 3.0, "unlimited": INF, "slide": INF, "ball:wx": INF,
                            "ball:wy": INF, "ball:wz": INF, "clamped": 20.0, "frc_only": 0.7,
                            "tendon_only": INF},
}


def mujoco_largest_joint_forces(mj, actuators) -> np.ndarray:
    """Per MuJoCo DOF, the largest |qfrc_actuator| over every corner of ctrl = +-1e6 on `actuators` (the
    others at 0), at qpos0 and rest: MuJoCo clamps ctrl, actuator forces and joint totals where the file says,
    and each force is monotonic in its ctrl, so a bounded DOF reaches its bound at a corner."""
    data = mujoco.MjData(mj)
    largest = np.zeros(mj.nv)
    for signs in itertools.product((-1e6, 1e6), repeat=len(actuators)):
        data.ctrl[:] = 0.0
        data.ctrl[actuators] = signs
        mujoco.mj_forward(mj, data)
        largest = np.maximum(largest, np.abs(data.qfrc_actuator))
    return largest


@pytest.mark.parametrize("flags", sorted(EFFORT_LIMITS))
def test_actuators_give_effort_limits_that_mujoco_reaches(flags, tmp_path):
    """Each DOF's effort limit is the largest actuator force MuJoCo applies to it: reached at a corner of the
    controls where finite, beyond 1e6 where there is none. Checked against the compiled arrays too (the motor's
    gear times ctrlrange, the servo's forcerange, the bare joint's actuatorfrcrange); model files keep them."""
    with pytest.warns(MjcfIgnoredWarning) as record:
        loaded = load_mjcf_with_map(ACTUATED.format(flags=flags))
    (message,) = [str(w.message) for w in record]
    assert "1 actuators not on a hinge, slide or ball joint, giving no effort limit (pull)" in message
    m, mj = loaded.model, loaded.mujoco_model
    limits = dict(zip(m.dof_names, m.effort_limits))
    assert limits == EFFORT_LIMITS[flags]
    assert np.array_equal(loaded.velocity_map(soadyn.neutral_configuration(m)), np.eye(m.nv))  # MuJoCo's DOF order
    on_joints = [k for k in range(mj.nu) if mj.actuator_trntype[k] == mujoco.mjtTrn.mjTRN_JOINT]
    largest = mujoco_largest_joint_forces(mj, on_joints)
    actuated = np.array([not name.startswith(("frc_only", "tendon_only")) for name in m.dof_names])
    finite = np.isfinite(m.effort_limits)
    np.testing.assert_allclose(largest[finite & actuated], m.effort_limits[finite & actuated], rtol=1e-12)
    assert np.all(largest[~finite & actuated] >= 1e6)
    motor, servo = (mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_ACTUATOR, name) for name in ("motor", "servo"))
    assert limits["frc_only"] == np.abs(mj.jnt_actfrcrange[mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_JOINT,
                                                                             "frc_only")]).max()
    assert limits["servo"] == np.abs(mj.actuator_forcerange[servo]).max()
    if not flags:
        assert limits["motor"] == mj.actuator_gear[motor, 0] * np.abs(mj.actuator_ctrlrange[motor]).max()
    soadyn.save_model(m, tmp_path / "actuated.json")
    assert np.array_equal(soadyn.load_model(tmp_path / "actuated.json").effort_limits, m.effort_limits)


def test_actuators_giving_no_effort_limit_are_named():
    """A motor on a free joint (its force is in MuJoCo's world frame, soadyn's DOFs in the body's) and one whose
    gear is zero give no limit: both named, with the joint whose actuators apply no force."""
    xml = """<mujoco><worldbody><body name="base"><freejoint name="float"/><geom size="0.1" mass="1"/>
      <body name="arm" pos="0 0 -0.3"><joint name="idle" axis="0 1 0"/><geom size="0.1" mass="1"/></body></body>
      </worldbody><actuator><motor name="thrust" joint="float" gear="0 0 1 0 0 0" ctrlrange="-1 1"/>
      <motor name="geared_off" joint="idle" gear="0" ctrlrange="-1 1"/></actuator></mujoco>"""
    with pytest.warns(MjcfIgnoredWarning) as record:
        m = soadyn.load_mjcf(xml)
    message = str(record[0].message)
    assert "1 actuators not on a hinge, slide or ball joint, giving no effort limit (thrust)" in message
    assert "1 joints whose actuators can apply no force, given no effort limit (idle)" in message
    assert "2 actuators (thrust, geared_off)" in message
    assert np.all(m.effort_limits == np.inf)
