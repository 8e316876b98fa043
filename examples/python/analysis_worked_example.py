"""The analysis layer worked through: a four-bar's equilibrium and its design sensitivities, an
LQR controller for a two-link arm from its exact linearization, and the arm's modes (plotted).

    python examples/python/analysis_worked_example.py [--plot modes.png]
"""
from __future__ import annotations

import argparse

import numpy as np
from scipy.linalg import solve_continuous_are

import soadyn


def four_bar_with_crank_spring():
    """Crank 0.4 m, coupler 1.0 m, rocker 0.8 m, pivots 0.9 m apart, in a vertical plane; a
    5 N m/rad torsion spring on the crank (rest angle 0); closed by a pin at the rocker's tip."""
    m = soadyn.Model()
    m.gravity = np.array([0.0, -9.81, 0.0])
    z = soadyn.Joint.revolute([0, 0, 1])

    def rod(length, mass):
        return dict(mass=mass, com=[length / 2, 0, 0],
                    inertia=np.diag([1e-4, mass * length ** 2 / 12, mass * length ** 2 / 12]))

    m.add_body("crank", "world", z, **rod(0.4, 1.2))
    m.add_body("coupler", "crank", z, placement=(np.eye(3), [0.4, 0, 0]), **rod(1.0, 2.0))
    m.add_body("rocker", "world", z, placement=(np.eye(3), [0.9, 0, 0]), **rod(0.8, 1.5))
    m.add_loop("pin", "coupler", "rocker", "point", placement_a=(np.eye(3), [1.0, 0, 0]),
               placement_b=(np.eye(3), [0.8, 0, 0]))
    m.add_joint_spring("crank_spring", "crank", 5.0, rest=0.0)
    return m


def four_bar_study() -> dict:
    m = four_bar_with_crank_spring()
    guess = soadyn.assemble(m, np.array([-1.0, 1.2, 1.8]), hold=["crank"])
    params = ["crank_spring.stiffness", "crank.mass", "coupler.mass", "rocker.mass"]
    eq = soadyn.static_equilibrium(m, guess, sensitivities=params)
    crank = m.dof_names.index("crank")
    print(f"four-bar: crank at rest at {eq.q[crank]:.6f} rad ({np.degrees(eq.q[crank]):.2f} deg), "
          f"stable: {eq.stable}, stiffness eigenvalues {eq.stiffness_eigenvalues}")
    for name in params:
        print(f"  d(crank angle)/d({name}) = {eq.sensitivities[name]['q'][crank]:+.6f}")
    # The same gradients for one scalar objective (the crank angle) by the adjoint method.
    objective = np.zeros(m.nv)
    objective[crank] = 1.0
    gradient = soadyn.objective_gradient(m, eq, params, objective)
    return {"equilibrium": eq, "adjoint": gradient, "model": m}


def two_link_arm():
    m = soadyn.Model()
    y = soadyn.Joint.revolute([0, 1, 0])
    for k, parent in enumerate(["world", "upper"]):
        name = ["upper", "fore"][k]
        m.add_body(name, parent, y, placement=(np.eye(3), [0, 0, 0.5 * k]), mass=1.0,
                   com=[0, 0, 0.25], inertia=np.diag([0.02, 0.02, 1e-3]))
    return m


def lqr_study() -> dict:
    """Stabilise the arm standing upright (q = 0, links along +z under gravity -z)."""
    m = two_link_arm()
    q, v = np.zeros(m.nv), np.zeros(m.nv)
    tau_hold = soadyn.inverse_dynamics(m, q, v, np.zeros(m.nv))  # zero upright: gravity acts through the joints
    A, B = soadyn.linearize(m, q, v, tau_hold)
    K = B.T @ solve_continuous_are(A, B, np.eye(2 * m.nv), np.eye(m.nv))  # R = I
    closed_loop = np.linalg.eigvals(A - B @ K)
    print(f"arm: open-loop eigenvalues {np.sort_complex(np.linalg.eigvals(A))}")
    print(f"arm: LQR closed-loop eigenvalues {np.sort_complex(closed_loop)} (all stable: "
          f"{bool((closed_loop.real < 0).all())})")
    # One Simulator step's exact linear map, for a discrete controller at 1 kHz.
    Ad, Bd = soadyn.linearize(m, q, v, tau_hold, dt=1e-3, integrator="rk4")
    return {"A": A, "B": B, "K": K, "closed_loop": closed_loop, "Ad": Ad, "Bd": Bd}


def modes_study(plot: str | None) -> soadyn.Modes:
    m = two_link_arm()
    hanging = np.array([np.pi, 0.0])
    modes = soadyn.modes(m, hanging)
    print("arm hanging down:\n" + modes.table())
    if plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 3))
        for k, shape in enumerate(modes.shapes):
            ax.bar(np.arange(len(shape)) + 0.35 * k, shape, width=0.35,
                   label=f"mode {k + 1}: {modes.frequencies_hz[k]:.3f} Hz")
        ax.set_xticks(np.arange(len(modes.dof_names)) + 0.175, modes.dof_names)
        ax.set_ylabel("mode shape")
        ax.legend()
        fig.tight_layout()
        fig.savefig(plot)
        print(f"wrote {plot}")
    return modes


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="write the arm's mode shapes to this PNG")
    args = parser.parse_args(argv)
    return {"four_bar": four_bar_study(), "lqr": lqr_study(), "modes": modes_study(args.plot)}


if __name__ == "__main__":
    main()
