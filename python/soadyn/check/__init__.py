"""soadyn against independent libraries: `soadyn check` (cross_check.py) and the oracle adapters it uses.

Pinocchio and DART on URDF files (oracles.py), MuJoCo on URDF and MJCF files (mujoco_oracle.py), and
Pinocchio's own MJCF parser (pinocchio_mjcf.py); each loads the file with its own parser and matches its
DOFs to soadyn's by name. `python -m soadyn.check FILE` is `soadyn check FILE`.
"""
from .cross_check import (CheckReport, Difference, cross_check, cross_check_report, format_report, format_table,
                          is_mjcf, random_joint_mask, random_states, relative_difference, rigid_part)

__all__ = ["CheckReport", "Difference", "cross_check", "cross_check_report", "format_report", "format_table",
           "is_mjcf", "random_joint_mask", "random_states", "relative_difference", "rigid_part"]
