"""The C++ timing loop and the names of the kernels chosen at run time, imported here and only here.

time_cpp(model, algorithm, q, v, u, calls, repetitions=7): median microseconds per C++ call of an
algorithm cycling through the rows of q, v, u. joint_angle_kernel(), mass_matrix_kernel(): the
kernels this processor runs.
"""
try:
    from soadyn._timing import joint_angle_kernel, mass_matrix_kernel, time_cpp
except ImportError:  # a build without soadyn._timing: the same functions in soadyn._soadyn
    from soadyn._soadyn import _joint_angle_kernel as joint_angle_kernel
    from soadyn._soadyn import _mass_matrix_kernel as mass_matrix_kernel
    from soadyn._soadyn import _time_cpp as time_cpp

__all__ = ["joint_angle_kernel", "mass_matrix_kernel", "time_cpp"]
