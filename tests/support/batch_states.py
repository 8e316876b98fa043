"""Seeded batches of states for the batched calls' tests: random configurations (one seed per row) and
velocities and inputs uniform in [-1, 1]."""
from __future__ import annotations

import numpy as np

import soadyn


def batch_states(m: soadyn.Model, rows: int, seed: int = 0):
    """(Q, V, X): rows x nq configurations, rows x nv velocities and inputs."""
    rng = np.random.default_rng(seed)
    Q = np.array([soadyn.random_configuration(m, seed * 1000 + k) for k in range(rows)]).reshape(rows, m.nq)
    V, X = rng.uniform(-1, 1, (2, rows, m.nv))
    return Q, V, X
