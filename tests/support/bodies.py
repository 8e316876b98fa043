"""Single bodies for simulator tests."""
import soadyn


def tumbling_body():
    """A free body, its centre of mass off the body origin and its principal moments distinct, without gravity."""
    m = soadyn.Model()
    m.add_body("body", None, soadyn.Joint.free(), mass=2.0, com=[0.1, 0, 0], inertia=[1.0, 2.0, 2.5])
    m.gravity = [0, 0, 0]
    return m
