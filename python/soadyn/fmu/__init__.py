"""FMU export: soadyn models as Functional Mock-up Units (FMI 3.0 and 2.0 co-simulation) for HIL rigs and
system simulators (the FMU guide, docs/guides/fmu.md).

export_fmu writes an FMU that runs without Python: the generic binary built with the package
(soadyn_fmu.so, cpp/src/fmu/), the model file and the FMU's settings as resources, and the
modelDescription.xml that binary writes for the model (so the description and the binary agree).
"""
from .export import FMI_VERSIONS, FmuError, export_fmu, fmu_binary

__all__ = ["export_fmu", "FmuError", "FMI_VERSIONS", "fmu_binary"]
