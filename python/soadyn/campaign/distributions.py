"""The distributions a dispersion draws from: normal, uniform, lognormal.

Each draw takes one call of a numpy Generator, so a run's values depend only
on its generator and on the order of the dispersions in the spec.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from .problems import finite_number, shown

DISTRIBUTIONS = ("normal", "uniform", "lognormal")

# The keys each distribution reads from a [[dispersions]] entry.
DISTRIBUTION_KEYS = {
    "normal": ("mean", "std", "scale"),
    "uniform": ("low", "high", "scale"),
    "lognormal": ("median", "sigma"),
}


@dataclass(frozen=True)
class Distribution:
    """normal(mean, std), uniform(low, high) or lognormal(median, sigma) (log x ~ normal(log median, sigma))."""

    kind: str
    a: float  # normal: mean; uniform: low; lognormal: median
    b: float  # normal: std; uniform: high; lognormal: sigma

    def draw(self, rng) -> float:
        if self.kind == "normal":
            return float(rng.normal(self.a, self.b))
        if self.kind == "uniform":
            return float(rng.uniform(self.a, self.b))
        return float(rng.lognormal(math.log(self.a), self.b))

    def to_dict(self) -> dict:
        """The resolved entry (absolute numbers), as the spec would write it."""
        names = {"normal": ("mean", "std"), "uniform": ("low", "high"), "lognormal": ("median", "sigma")}[self.kind]
        return {"distribution": self.kind, names[0]: self.a, names[1]: self.b}

    def __str__(self) -> str:
        d = self.to_dict()
        args = ", ".join(f"{k}={v:.6g}" for k, v in d.items() if k != "distribution")
        return f"{self.kind}({args})"


def real(entry: dict, key: str, where: str) -> float | None:
    """entry[key] as a finite float, None when absent; ValueError naming the key otherwise."""
    if key not in entry:
        return None
    value = entry[key]
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{where}: {key} must be a number, got {shown(value)}")
    if finite_number(value) is None:
        raise ValueError(f"{where}: {key} must be finite, got {shown(value)}")
    return float(value)


def parse_distribution(entry: dict, nominal: float | None, where: str, problems) -> Distribution | None:
    """The distribution of one [[dispersions]] entry, or None after adding its problems to `problems`
    (each naming `where` and the key at fault). `nominal` is the model's value of what is dispersed
    (None for event times and sources): the default mean / median, and what a relative `scale`
    multiplies."""
    kind = entry.get("distribution")
    if "distribution" not in entry:
        problems.add(f"{where}: distribution is required ({', '.join(DISTRIBUTIONS)})")
        return None
    if not isinstance(kind, str) or kind not in DISTRIBUTIONS:
        problems.add(f"{where}: distribution must be one of {', '.join(DISTRIBUTIONS)}, got {shown(kind)}")
        return None
    every_key = {k for keys in DISTRIBUTION_KEYS.values() for k in keys}
    foreign = sorted(every_key & set(entry) - set(DISTRIBUTION_KEYS[kind]))
    for key in foreign:
        problems.add(f"{where}: {key} is not a parameter of a {kind} distribution "
                     f"(it takes {', '.join(DISTRIBUTION_KEYS[kind])})")
    bad = object()
    values = {key: problems.check(real, entry, key, where, default=bad) for key in DISTRIBUTION_KEYS[kind]}
    if foreign or any(v is bad for v in values.values()):
        return None
    return problems.check(_resolved, kind, values, nominal, where)


def _resolved(kind: str, values: dict, nominal: float | None, where: str) -> Distribution:
    """The distribution from its checked keys (None: absent); ValueError naming `where` and the key."""
    def centre(key: str) -> float:
        if values[key] is not None:
            return values[key]
        if nominal is None:
            raise ValueError(f"{where}: give {key} (what is dispersed has no nominal value in the model)")
        return nominal

    def relative_scale() -> float:
        scale = values["scale"]
        if scale < 0:
            raise ValueError(f"{where}: scale must be >= 0, got {scale:g}")
        if nominal is None or nominal == 0:
            raise ValueError(f"{where}: scale is relative to the nominal value, which is "
                             f"{'absent' if nominal is None else 0}: give absolute numbers")
        spread = scale * abs(nominal)
        if not math.isfinite(spread):
            raise ValueError(f"{where}: scale {scale:g} times the nominal value {nominal:g} overflows")
        return spread

    if kind == "normal":
        if (values["std"] is None) == (values["scale"] is None):
            raise ValueError(f"{where}: a normal distribution needs std or scale (relative), one of the two")
        std = values["std"] if values["std"] is not None else relative_scale()
        if std < 0:
            raise ValueError(f"{where}: std must be >= 0, got {std:g}")
        return Distribution("normal", centre("mean"), std)
    if kind == "uniform":
        return _uniform(values, nominal, relative_scale, where)
    if values["sigma"] is None:
        raise ValueError(f"{where}: a lognormal distribution needs sigma (the std of the log)")
    if values["sigma"] < 0:
        raise ValueError(f"{where}: sigma must be >= 0, got {values['sigma']:g}")
    median = centre("median")
    if not median > 0:
        raise ValueError(f"{where}: a lognormal's median must be > 0, got {median:g}")
    return Distribution("lognormal", median, values["sigma"])


def _uniform(values: dict, nominal: float | None, relative_scale, where: str) -> Distribution:
    if values["scale"] is not None:
        if values["low"] is not None or values["high"] is not None:
            raise ValueError(f"{where}: a uniform distribution takes low and high, or scale, not both")
        half = relative_scale()
        low, high = nominal - half, nominal + half
    elif values["low"] is None or values["high"] is None:
        raise ValueError(f"{where}: a uniform distribution needs low and high (or a relative scale)")
    else:
        low, high = values["low"], values["high"]
    if low > high:
        raise ValueError(f"{where}: low {low:g} is above high {high:g}")
    if not math.isfinite(high - low):
        raise ValueError(f"{where}: high - low overflows ({low:g} to {high:g}): draws would not be finite")
    return Distribution("uniform", low, high)
