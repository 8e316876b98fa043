"""export_fmu: a model into an .fmu archive (FMI 3.0 or 2.0 co-simulation, x86-64 Linux binary)."""
from __future__ import annotations

import ctypes
import datetime
import os
import re
import uuid
import zipfile
from pathlib import Path

import numpy as np

from .._version import __version__
from .._soadyn import neutral_configuration
from ..io.model_file import model_to_json
from ..loops import assemble
from ..model import Model
from ..output_paths import output_problem

FMI_VERSIONS = (3, 2)
"""The FMI versions export_fmu writes (co-simulation)."""

INTEGRATORS = ("rk4", "euler", "dopri5")
INPUT_KINDS = ("acceleration", "velocity", "position")
"""What the input u.<dof> of a prescribed DOF can give (export_fmu's input_kinds)."""
# Where each FMI version's standard puts an x86-64 Linux binary in the archive.
_PLATFORM_FOLDER = {3: "x86_64-linux", 2: "linux64"}


class FmuError(ValueError):
    """An FMU cannot be written: a bad argument (named), a model whose start state the FMU cannot take, or
    the FMU binary missing from this installation."""


def fmu_binary() -> Path:
    """The generic FMU binary built with this package (soadyn/fmu/soadyn_fmu.so); FmuError if absent."""
    path = Path(__file__).with_name("soadyn_fmu.so")
    if not path.is_file():
        raise FmuError(f"the FMU binary {path} is missing from this installation (reinstall soadyn)")
    return path


def _identifier(name: str) -> str:
    """A C identifier from `name` (FMI's modelIdentifier names the binary's file)."""
    text = re.sub(r"\W", "_", name)
    return text if text and not text[0].isdigit() else f"m_{text}"


def _state(model: Model, values, size: int, what: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise FmuError(f"{what} must be {size} finite numbers, got shape {array.shape}")
    return np.ascontiguousarray(array)


def _start(model: Model, q0, v0) -> tuple[np.ndarray, np.ndarray]:
    """The start state: given, or the neutral configuration at rest (closed first on a loop model)."""
    if q0 is None:
        q0 = neutral_configuration(model)
        if model.nloops:
            q0 = assemble(model, q0)
    v0 = np.zeros(model.nv) if v0 is None else v0
    return _state(model, q0, model.nq, "q0"), _state(model, v0, model.nv, "v0")


def _frames(model: Model, outputs) -> list[str]:
    """The frame names of `outputs` ("frame.<name>" each); FmuError for anything else."""
    if isinstance(outputs, str):
        outputs = [outputs]
    frames = []
    for item in outputs:
        if not isinstance(item, str) or not item.startswith("frame.") or len(item) == 6 or " " in item:
            raise FmuError(f"outputs: {item!r} is not 'frame.<name>' (a body or frame name without spaces; the "
                           f"model's: {', '.join(model.body_names + model.frame_names)})")
        frames.append(item[len("frame."):])
    return frames


def _names(model: Model, frames, what: str) -> list[str]:
    """Frame names (a body or frame of the model, no spaces); FmuError naming a wrong one."""
    if isinstance(frames, str):
        frames = [frames]
    known = model.body_names + model.frame_names
    for name in frames:
        if not isinstance(name, str) or name not in known:
            raise FmuError(f"{what}: {name!r} is not a body or frame of the model ({', '.join(known)})")
    return list(frames)


def _input_kinds(model: Model, kinds) -> list[str]:
    """{DOF: kind} as "<dof>=<kind>" items; FmuError naming an unknown DOF or kind."""
    if not isinstance(kinds, dict):
        raise FmuError(f"input_kinds must be a dict {{DOF name: kind}}, got {type(kinds).__name__}")
    items = []
    for dof, kind in kinds.items():
        if dof not in model.dof_names:
            raise FmuError(f"input_kinds: {dof!r} is not a DOF of the model ({', '.join(model.dof_names)})")
        if kind not in INPUT_KINDS:
            raise FmuError(f"input_kinds[{dof!r}] must be one of {', '.join(INPUT_KINDS)}, got {kind!r}")
        items.append(f"{dof}={kind}")
    return items


def export_fmu(model, path, fmi: int = 3, step: float = 1e-3, substeps: int = 1, integrator: str = "rk4",
               q0=None, v0=None, outputs=(), name: str | None = None, description: str = "", wrenches=(),
               input_kinds=None) -> Path:
    """Write `model` as a co-simulation FMU at `path` (.fmu) and return the path.

    model: a soadyn.Model, or what `soadyn view` takes by name (a built-in scene, a model file, an MJCF or
    URDF file, an example robot). fmi: 3 or 2. step: the communication step the FMU's default experiment
    gives, in s; the FMU integrates with `integrator` ("rk4", "euler", "dopri5") at step / substeps, and a
    DoStep of h runs h / (step / substeps) steps (h must be a whole number of them). q0, v0: the start
    state ((nq,), (nv,); default the neutral configuration at rest, closed first on a loop model).
    outputs: the extra outputs, "frame.<name>" for a body or frame: its world position, world quaternion,
    angular and linear velocity and classical acceleration in its own axes (frame.<name>.x ... .az; the
    FMU guide lists them). name: the modelName (default the scene's name or "soadyn_model"). wrenches: the
    bodies or frames that take an external wrench input, wrench.<frame>.tx ... .fz ([torque; force] in the
    frame's own axes about its origin). input_kinds: {DOF name: "acceleration", "velocity" or "position"},
    what u.<dof> gives when the DOF is prescribed (default acceleration; the FMU guide gives the motions).

    The FMU's variables (fixed names): inputs u.<dof> (torque or force of a regular DOF; acceleration,
    velocity or position of a prescribed one per input_kinds; held over each communication step),
    locked.<dof> and prescribed.<dof> (Booleans: the mode switches), wrench.<frame>.*; outputs q.<coordinate>,
    v.<dof>, qdd.<dof> and tau.<dof> (the accelerations and generalized forces at the communication point),
    energy.kinetic, energy.potential, loop.<loop>.*, frame.<name>.*; parameters integrator (an enumeration,
    fixed), substeps (fixed) and the model's parameters (tunable but for the placements); SI units.

    Raises FmuError naming the argument at fault (or the start state the simulator refuses), TypeError for
    a model of another type, and OSError naming the path when it cannot be written.
    """
    if isinstance(model, (str, os.PathLike)):
        from ..viz.sources import load_any

        source = os.fspath(model)
        model, name = load_any(source), name or Path(source).stem
    if not isinstance(model, Model):
        raise TypeError(f"export_fmu needs a soadyn.Model or a model's name or file, got {type(model).__name__}")
    if fmi not in FMI_VERSIONS:
        raise FmuError(f"fmi must be 3 or 2, got {fmi!r}")
    if integrator not in INTEGRATORS:
        raise FmuError(f"integrator must be one of {', '.join(INTEGRATORS)}, got {integrator!r}")
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not np.isfinite(step) or step <= 0:
        raise FmuError(f"step must be a finite number of seconds > 0, got {step!r}")
    if isinstance(substeps, bool) or not isinstance(substeps, int) or not 1 <= substeps <= 1_000_000:
        raise FmuError(f"substeps must be a whole number from 1 to 1000000, got {substeps!r}")
    problem = output_problem(path)
    if problem:
        raise OSError(f"the FMU '{os.fspath(path)}': {problem}")
    path = Path(path)
    q0, v0 = _start(model, q0, v0)
    frames = _frames(model, outputs)
    wrench_frames = _names(model, wrenches, "wrenches")
    kinds = _input_kinds(model, {} if input_kinds is None else input_kinds)
    name = name or "soadyn_model"
    identifier = _identifier(name)
    token = "{" + str(uuid.uuid4()) + "}"
    binary = fmu_binary()
    library = ctypes.CDLL(str(binary))
    describe = library.soadyn_fmu_describe
    describe.restype = ctypes.c_int
    double_array = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
    describe.argtypes = [ctypes.c_char_p, ctypes.c_int, ctypes.c_double, ctypes.c_int, ctypes.c_char_p, double_array,
                         double_array] + [ctypes.c_char_p] * 9
    for getter in ("soadyn_fmu_description_xml", "soadyn_fmu_settings_text", "soadyn_fmu_error"):
        getattr(library, getter).restype = ctypes.c_char_p
    model_json = model_to_json(model)
    now = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat().replace("+00:00", "Z")
    texts = [model_json, name, identifier, token, description, f"soadyn {__version__}", now]
    if describe(texts[0].encode(), fmi, float(step), substeps, integrator.encode(), q0, v0, " ".join(frames).encode(),
                " ".join(wrench_frames).encode(), " ".join(kinds).encode(), *(t.encode() for t in texts[1:])) != 0:
        raise FmuError(f"cannot export the FMU: {library.soadyn_fmu_error().decode()}")
    xml = library.soadyn_fmu_description_xml().decode()
    settings = library.soadyn_fmu_settings_text().decode()
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("modelDescription.xml", xml)
        archive.write(binary, f"binaries/{_PLATFORM_FOLDER[fmi]}/{identifier}.so")
        archive.writestr("resources/model.json", model_json)
        archive.writestr("resources/soadyn_fmu.txt", settings)
    return path
