"""Energy and its rate along the motion: the total mechanical energy T + V of a model, and the time
derivative of any function of the state along qdot = v, vdot = qdd."""
import soadyn


def flow_derivative(fn, m, q, v, qdd, eps=1e-6):
    """d/dt fn(q, v) along qdot = v (on the joint manifolds), vdot = qdd; central difference.

    The first-order position update errs by the same +-(1/2) qdd eps^2 in
    both directions, so the central difference stays O(eps^2) accurate.
    """
    ahead = fn(m, soadyn.integrate(m, q, v, eps), v + eps * qdd)
    behind = fn(m, soadyn.integrate(m, q, v, -eps), v - eps * qdd)
    return (ahead - behind) / (2 * eps)


def total_energy(m, q, v):
    return soadyn.kinetic_energy(m, q, v) + soadyn.potential_energy(m, q)
