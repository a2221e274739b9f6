"""Linear modes followed over speed by their shape (docs/theory.md, "Mode tracking").

A mode's shape at one speed is matched to the shapes at the neighbouring speed by the modal
assurance criterion (Allemang and Brown, "A correlation coefficient for modal vector
analysis", 1982) of the mass-weighted position parts ``phi = sqrt(M_ii) x_i``:

    MAC(a, b) = |phi_a^H phi_b|^2 / ((phi_a^H phi_a) (phi_b^H phi_b))

One assignment per pair of speeds (the Hungarian method on ``1 - MAC``) links the modes into
branches; a pair with MAC below :data:`MAC_MIN` is not linked (the branch ends, a new one
starts). A branch's damping ratio changes sign where the damping of *that* mode crosses zero,
not where the least damped mode of a frequency band or a name changes, which is what made the
EU07's "wheelset hunting" jump from 3.0 to 9.3 Hz.

Each branch gets the name of its mode where it is least damped (:func:`branch_label`), made
unique by a number ("car-body roll 2"), and its unstable bands: the speed intervals where its
damping ratio is zero or below, each end refined by secant steps on the branch.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

#: Shapes with a MAC below this are different modes (railexu's choice: half the shape alike).
MAC_MIN = 0.5
#: Modes listed per speed in the table of least damped modes.
TABLE_MODES = 4


@dataclass
class Branch:
    """One mode followed over speed: per speed index its mode (or None where not found)."""

    modes: dict[int, object] = field(default_factory=dict)
    macs: list[float] = field(default_factory=list)
    label: str = ""

    def last(self) -> tuple[int, object]:
        k = max(self.modes)
        return k, self.modes[k]


def mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion of two complex shapes (0: unrelated, 1: the same shape)."""
    num = abs(np.vdot(a, b)) ** 2
    den = float(np.real(np.vdot(a, a)) * np.real(np.vdot(b, b)))
    return float(num / den) if den > 0.0 else 0.0


def _mac_matrix(old: list, new: list) -> np.ndarray:
    return np.array([[mac(o.shape, n.shape) for n in new] for o in old]).reshape(len(old), len(new))


def track_branches(per_speed: list[list]) -> list[Branch]:
    """Link the modes at successive speeds (each with a ``shape``) into branches by MAC."""
    from scipy.optimize import linear_sum_assignment

    branches: list[Branch] = []
    open_ids: list[int] = []
    for k, modes in enumerate(per_speed):
        live = [branches[i] for i in open_ids]
        macs = _mac_matrix([b.last()[1] for b in live], modes)
        linked: dict[int, int] = {}
        if macs.size:
            rows, cols = linear_sum_assignment(-macs)
            for r, c in zip(rows, cols, strict=True):
                if macs[r, c] >= MAC_MIN:
                    linked[int(c)] = open_ids[int(r)]
                    branches[open_ids[int(r)]].macs.append(float(macs[r, c]))
        next_open = []
        for j, mode in enumerate(modes):
            if j not in linked:
                branches.append(Branch())
                linked[j] = len(branches) - 1
            branches[linked[j]].modes[k] = mode
            next_open.append(linked[j])
        open_ids = next_open
    return branches


def branch_label(branch: Branch) -> str:
    """The name of the branch's mode where it is least damped."""
    mode = min(branch.modes.values(), key=lambda m: m.damping_ratio)
    return mode.name


def label_branches(branches: list[Branch]) -> None:
    """Unique labels: the branch's name, numbered from the second branch of that name on (the
    least damped branch of a name gets the plain name)."""
    by_name: dict[str, list[Branch]] = {}
    for b in branches:
        by_name.setdefault(branch_label(b), []).append(b)
    for name, group in by_name.items():
        group.sort(key=lambda b: min(m.damping_ratio for m in b.modes.values()))
        for i, b in enumerate(group):
            b.label = name if i == 0 else f"{name} {i + 1}"


def _refine(lo, hi, z_lo, z_hi, zeta_at: Callable, tolerance: float) -> float:
    """The speed between ``lo`` and ``hi`` where the damping ratio changes sign: secant steps
    (kept 5 % inside the bracket) on ``zeta_at(speed)``."""
    for _ in range(8):
        mid = lo + (hi - lo) * z_lo / (z_lo - z_hi)
        mid = min(max(mid, lo + 0.05 * (hi - lo)), hi - 0.05 * (hi - lo))
        z_mid = zeta_at(mid)
        if not math.isfinite(z_mid):
            break
        if (z_mid > 0.0) == (z_lo > 0.0):
            lo, z_lo = mid, z_mid
        else:
            hi, z_hi = mid, z_mid
        if hi - lo < 0.01 * tolerance:
            break
    return lo + (hi - lo) * z_lo / (z_lo - z_hi)


def unstable_bands(
    speeds: list[float], branch: Branch, modes_at: Callable, tolerance: float
) -> list[list[float | None]]:
    """The speed intervals ``[from, to]`` in which the branch's damping ratio is zero or below;
    ``from`` is None when unstable from the lowest speed it was followed at, ``to`` None when
    unstable up to the highest. Each sign change is refined on the branch: at an intermediate
    speed the mode with the largest MAC to the branch's shape at the bracket's lower end."""
    ks = sorted(branch.modes)
    bands: list[list[float | None]] = []
    start: float | None = None
    z_first = branch.modes[ks[0]].damping_ratio
    if z_first <= 0.0:
        start = None if ks[0] == 0 else speeds[ks[0]]
        bands.append([start, None])
    for k0, k1 in zip(ks[:-1], ks[1:], strict=True):
        m0, m1 = branch.modes[k0], branch.modes[k1]
        z0, z1 = m0.damping_ratio, m1.damping_ratio
        if (z0 > 0.0) == (z1 > 0.0):
            continue

        def zeta_at(v: float, shape=m0.shape) -> float:
            found = modes_at(v)
            if not found:
                return math.nan
            best = max(found, key=lambda m: mac(shape, m.shape))
            return best.damping_ratio if mac(shape, best.shape) >= MAC_MIN else math.nan

        v = _refine(speeds[k0], speeds[k1], z0, z1, zeta_at, tolerance)
        if z0 > 0.0:
            start = v
            bands.append([start, None])
        else:
            bands[-1][1] = v
    if bands and bands[-1][1] is None and ks[-1] < len(speeds) - 1:
        bands[-1][1] = speeds[ks[-1]]  # the branch ends (no longer found) while unstable
    return bands


def least_damped_table(speeds: list[float], branches: list[Branch]) -> list[dict]:
    """Per speed the :data:`TABLE_MODES` least damped modes: ``speed_m_per_s`` and ``modes``,
    a list of ``{mode, frequency_Hz, damping_ratio}`` (least damped first)."""
    rows = []
    for k, v in enumerate(speeds):
        here = [(b.label, b.modes[k]) for b in branches if k in b.modes]
        here.sort(key=lambda lm: lm[1].damping_ratio)
        rows.append({
            "speed_m_per_s": v,
            "modes": [{"mode": label, "frequency_Hz": m.frequency_Hz,
                       "damping_ratio": m.damping_ratio} for label, m in here[:TABLE_MODES]],
        })  # fmt: skip
    return rows
