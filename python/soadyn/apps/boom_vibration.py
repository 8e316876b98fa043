"""Vibration of cassini's flexible booms after an engine-gimbal step.

The spacecraft starts at rest with every drive held. At `t_step` the engine
gimbal's pitch axis, a prescribed DOF, slews by `step_deg` along a cycloidal
profile of `rise` seconds (finite acceleration, so a finite reaction); the
reaction shakes the bus, and the booms, clamped to it, ring at their natural
frequencies, damped by their 0.5 % modal damping. RK4 at `dt`, as in the
real-time runner. The tip deflection of each boom is its tip node's
displacement in the boom frame (the modal translation at the tip).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.modes import natural_frequencies
from ..simulator import MotionSource, Simulator


@dataclass
class BoomResponse:
    t: np.ndarray                       # (N,) s
    deflection: dict[str, np.ndarray]   # boom -> (N, 3) tip displacement in the boom frame, m
    peak: dict[str, float]              # boom -> largest tip displacement after the step, m
    dominant_hz: dict[str, float]       # boom -> strongest frequency of the tip motion after the slew
    linearised_hz: np.ndarray           # natural frequencies of the linearised scene (regular DOFs), Hz
    t_step: float
    rise: float


def _tip_translation_shape(body) -> np.ndarray:
    """3 x n_modes: the translation of the 'tip' node per unit modal coordinate."""
    return body.mode_shapes[body.attachments["tip"]][3:]


def _dominant_frequency(t: np.ndarray, x: np.ndarray) -> float:
    """Frequency (Hz) of the largest peak of the spectrum of x (N, 3), zero-padded 16x."""
    x = x - x.mean(axis=0)
    n = 16 * len(t)
    spectrum = sum(np.abs(np.fft.rfft(x[:, k] * np.hanning(len(t)), n)) for k in range(x.shape[1]))
    freqs = np.fft.rfftfreq(n, t[1] - t[0])
    spectrum[freqs < 0.05] = 0.0  # ignore the slow drift of the slewed spacecraft
    return float(freqs[np.argmax(spectrum)])


def gimbal_step_response(model, step_deg: float = 2.0, rise: float = 0.2, t_step: float = 1.0,
                         duration: float = 20.0, dt: float = 1e-3) -> BoomResponse:
    """Simulate the gimbal step on a cassini model and measure the booms' tip motion."""
    if not duration >= t_step + rise + 1.0:
        raise ValueError(f"duration {duration:g} s leaves less than 1 s of ringing after the step "
                         f"(it ends at {t_step + rise:g} s)")
    booms = [name for name, n in zip(model.body_names, model.n_modes) if n > 0]
    if not booms:
        raise ValueError("the scene has no flexible body")
    if model.dof_index("gimbal_pitch") < 0:
        raise ValueError("the scene has no 'gimbal_pitch' DOF")
    sim = Simulator(model, dt, "rk4")
    sim.schedule(t_step, "prescribe", "gimbal_pitch",
                 MotionSource.cycloidal(0.0, np.radians(step_deg), t_step, rise))
    trajectory = sim.run(duration)
    t = trajectory.t
    deflection, peak, dominant = {}, {}, {}
    ringing = t >= t_step + rise
    for name in booms:
        body = model.flexible_body(name)
        first = model.dof_names.index(f"{name}:mode1")
        k = model.coordinate_names.index(model.dof_names[first])
        eta = trajectory.q[:, k:k + body.n_modes]
        deflection[name] = eta @ _tip_translation_shape(body).T
        peak[name] = float(np.linalg.norm(deflection[name], axis=1).max())
        dominant[name] = _dominant_frequency(t[ringing], deflection[name][ringing])
    linearised = natural_frequencies(model, trajectory.q[0]) / (2 * np.pi)  # drives held
    return BoomResponse(t, deflection, peak, dominant, linearised[linearised > 1e-6], t_step, rise)


def format_response(r: BoomResponse) -> str:
    lines = [f"boom vibration after a gimbal_pitch step at t = {r.t_step:g} s ({r.rise:g} s cycloidal slew)"]
    for name in r.deflection:
        nearest = r.linearised_hz[np.argmin(np.abs(r.linearised_hz - r.dominant_hz[name]))]
        lines.append(f"  {name:<22} peak tip deflection {r.peak[name] * 1e3:8.3f} mm, rings at "
                     f"{r.dominant_hz[name]:.3f} Hz (linearised mode {nearest:.3f} Hz)")
    return "\n".join(lines)


def plot_response(r: BoomResponse, path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4))
    for name, d in r.deflection.items():
        ax.plot(r.t, np.linalg.norm(d, axis=1) * 1e3, label=name)
    ax.axvspan(r.t_step, r.t_step + r.rise, color="0.9", label="gimbal slew")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("tip deflection (mm)")
    ax.set_title("cassini booms after an engine-gimbal step")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
