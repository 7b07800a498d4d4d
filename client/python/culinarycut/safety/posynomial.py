"""F_hat = sum_k c_k prod_j x_j^a_kj with every c_k >= 0 and a_kj >= 0: a posynomial, so it never falls as
the knife speeds up (the limiter's bisection for the safe speed relies on that)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# The model's inputs, in the units their names say (the asset's "inputs", in this order).
INPUTS = ("speed_m_s", "youngs_modulus_mpa", "yield_stress_kpa", "fracture_toughness_j_m2", "edge_length_m")
SPEED = INPUTS.index("speed_m_s")


def monomials(x: np.ndarray, exponents: np.ndarray) -> np.ndarray:
    """(N, K) values of K monomials at N points; 0^0 is 1 (a term without speed at a still knife)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    return np.prod(np.where(exponents[None, :, :] == 0, 1.0, x[:, None, :] ** exponents[None, :, :]), axis=2)


@dataclass(frozen=True)
class Posynomial:
    coefficients: np.ndarray  # (K,), each >= 0, N per unit of its monomial
    exponents: np.ndarray     # (K, len(INPUTS)), each >= 0

    def __post_init__(self):
        if self.exponents.ndim != 2 or self.exponents.shape[1] != len(INPUTS):
            raise ValueError(f"exponents: need shape (K, {len(INPUTS)}), got {self.exponents.shape}")
        if np.any(self.coefficients < 0) or np.any(self.exponents < 0):
            raise ValueError("a posynomial needs non-negative coefficients and exponents")

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Force (N) at each row of x (inputs in INPUTS order)."""
        return monomials(x, self.exponents) @ self.coefficients

    def terms(self) -> list[dict]:
        """The asset's "terms", zero coefficients left out."""
        return [{"coefficient": float(c), "exponents": [float(a) for a in row]}
                for c, row in zip(self.coefficients, self.exponents) if c > 0]
