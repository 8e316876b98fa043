"""The clamped-free Euler-Bernoulli beam in closed form: its natural frequencies."""
import numpy as np

# beta_i L of the clamped-free beam, roots of 1 + cos x cosh x = 0
# (Blevins, "Formulas for natural frequency and mode shape", table 8-1).
BETA_L = np.array([1.87510406871196, 4.69409113297418, 7.85475743823761, 10.9955407348755])


def euler_bernoulli_frequencies(beta_l, length, EI, mass_per_length):
    """omega_i = (beta_i L)^2 sqrt(EI / (mu L^4)) in rad/s."""
    return beta_l ** 2 * np.sqrt(EI / (mass_per_length * length ** 4))
