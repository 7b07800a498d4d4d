"""Fit the posynomial force model by non-negative least squares (scipy.optimize.nnls) on candidate monomials.
Non-negative coefficients on monomials with non-negative exponents make the model nondecreasing in speed by
construction, so no fit can give the limiter a force that falls as the knife speeds up. The monomial set is
chosen from a small family of candidates by cross-validation on the training rows; the held-out rows (a
seeded split) only measure the chosen model."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import nnls

from culinarycut.safety.posynomial import INPUTS, SPEED, Posynomial, monomials

# Exponents in INPUTS order: (speed, E, yield stress, toughness, edge length). Every family grows the last;
# the force to cut is toughness x edge length (G_c L) plus the faces' friction, which grows with the edge in
# the food and may grow with speed, stiffness and strength.
_EDGE = [(0, 0, 0, 1, 1), (0, 0, 0, 0, 1)]
_SPEED = [(1, 0, 0, 0, 1), (2, 0, 0, 0, 1)]
_MATERIAL = [(0, 0.5, 0, 0, 1), (0, 1, 0, 0, 1), (0, 0, 1, 0, 1)]
_CROSS = [(1, 0.5, 0, 0, 1), (1, 0, 1, 0, 1), (1, 0, 0, 1, 1), (2, 0, 0, 1, 1)]
_AREA = [(0, 0, 0, 1, 2), (0, 0, 0, 0, 2), (0, 0.5, 0, 0, 2), (1, 0, 0, 0, 2), (0, 0, 0, 0, 0)]
FAMILIES: dict[str, list[tuple]] = {
    "toughness x edge": _EDGE,
    "+ speed": _EDGE + _SPEED,
    "+ stiffness, strength": _EDGE + _SPEED + _MATERIAL,
    "+ speed x material": _EDGE + _SPEED + _MATERIAL + _CROSS,
    "+ edge squared, constant": _EDGE + _SPEED + _MATERIAL + _CROSS + _AREA,
}
FOLDS = 5
# A larger family must beat a smaller one's cross-validated RMSE by more than this to be chosen.
SIMPLER_WITHIN = 0.05


def nnls_fit(x: np.ndarray, y: np.ndarray, exponents: np.ndarray) -> Posynomial:
    """Least squares with every coefficient >= 0; columns scaled to unit norm for conditioning."""
    design = monomials(x, exponents)
    scale = np.linalg.norm(design, axis=0)
    scale[scale == 0] = 1.0
    scaled, _ = nnls(design / scale, y)
    return Posynomial(coefficients=scaled / scale, exponents=exponents)


def errors(model: Posynomial, x: np.ndarray, y: np.ndarray) -> dict:
    residual = model(x) - y
    total = float(np.sum((y - y.mean()) ** 2))
    return {"r2": 1.0 - float(np.sum(residual ** 2)) / total if total > 0 else float("nan"),
            "rmse_n": float(np.sqrt(np.mean(residual ** 2))), "max_abs_error_n": float(np.max(np.abs(residual)))}


def monotonic_in_speed(model: Posynomial, x: np.ndarray, speed_range: tuple[float, float], points: int = 200) -> bool:
    """Check on a grid: for every material row of x, the force at 0 and at speeds across the range never falls."""
    speeds = np.concatenate([[0.0], np.geomspace(speed_range[0], speed_range[1], points)])
    for row in np.unique(np.delete(x, SPEED, axis=1), axis=0):
        grid = np.insert(np.repeat(row[None, :], len(speeds), axis=0), SPEED, speeds, axis=1)
        force = model(grid)
        if np.any(np.diff(force) < -1e-12 * max(1.0, float(np.abs(force).max()))):
            return False
    return True


@dataclass
class FitResult:
    model: Posynomial
    family: str
    held_out: dict               # r2, rmse_n, max_abs_error_n on the held-out rows
    train: dict
    cross_validation: dict = field(default_factory=dict)  # family -> cross-validated RMSE (N)
    samples: int = 0
    held_out_count: int = 0
    monotonic_in_speed: bool = False
    held_out_rows: np.ndarray | None = None  # indices into the rows fitted


def split(count: int, held_out_fraction: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """A seeded random split of row indices: (train, held out)."""
    order = np.random.default_rng(seed).permutation(count)
    held = max(1, int(round(held_out_fraction * count)))
    return np.sort(order[held:]), np.sort(order[:held])


def _cross_validated_rmse(x: np.ndarray, y: np.ndarray, exponents: np.ndarray, seed: int) -> float:
    folds = np.array_split(np.random.default_rng(seed).permutation(len(y)), min(FOLDS, len(y)))
    squared = []
    for fold in folds:
        train = np.setdiff1d(np.arange(len(y)), fold)
        model = nnls_fit(x[train], y[train], exponents)
        squared.append((model(x[fold]) - y[fold]) ** 2)
    return float(np.sqrt(np.mean(np.concatenate(squared))))


def fit_force_model(x: np.ndarray, y: np.ndarray, seed: int = 0, held_out_fraction: float = 0.2,
                    families: dict[str, list[tuple]] | None = None) -> FitResult:
    """Choose the family by cross-validation on the training rows, fit it on them, measure it on the rest."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.ndim != 2 or x.shape[1] != len(INPUTS) or len(y) != len(x):
        raise ValueError(f"need x of shape (N, {len(INPUTS)}) and N forces")
    if len(y) < 2 * FOLDS:
        raise ValueError(f"need at least {2 * FOLDS} samples to fit, got {len(y)}")
    families = families or FAMILIES
    train, held = split(len(y), held_out_fraction, seed)
    cv = {name: _cross_validated_rmse(x[train], y[train], np.array(exps, dtype=float), seed + 1)
          for name, exps in families.items()}
    best = min(cv.values())
    # The smallest family within SIMPLER_WITHIN of the best: more monomials must earn their place.
    family = min((name for name in families if cv[name] <= best * (1 + SIMPLER_WITHIN) + 1e-12),
                 key=lambda name: len(families[name]))
    model = nnls_fit(x[train], y[train], np.array(families[family], dtype=float))
    speed_range = (float(x[:, SPEED].min()), float(x[:, SPEED].max()))
    return FitResult(model=model, family=family, held_out=errors(model, x[held], y[held]),
                     train=errors(model, x[train], y[train]), cross_validation=cv, samples=len(y),
                     held_out_count=len(held), monotonic_in_speed=monotonic_in_speed(model, x, speed_range),
                     held_out_rows=held)
