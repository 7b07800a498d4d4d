"""The sweep: which cuts a force dataset holds (speeds x materials x foods x scales), each as a cc-cut scene."""
from __future__ import annotations

import itertools
from dataclasses import asdict, dataclass, field

import numpy as np

# The engine's foods (sim/mpm/food_shapes.cc); cc-cut refuses any other.
FOODS = ("apple", "banana", "cucumber", "melon", "orange", "peach", "strawberry")
MAX_SPEED_M_S = 20.0  # cc-cut's knife.descent_speed_m_s range is (0, 20]


def log_speeds(low_m_s: float, high_m_s: float, count: int) -> tuple[float, ...]:
    """count speeds log-spaced from low to high (m/s), rounded to 4 significant digits."""
    return tuple(float(f"{v:.4g}") for v in np.geomspace(low_m_s, high_m_s, count))


@dataclass(frozen=True)
class Sample:
    """One cut: a food at a scale, a material, a knife speed."""
    food: str
    scale: float
    youngs_modulus_mpa: float
    yield_stress_kpa: float
    fracture_toughness_j_m2: float
    speed_m_s: float

    def key(self) -> str:
        """A stable identifier: the same configuration always gives the same key (resume matches on it)."""
        return (f"{self.food}|s{self.scale:g}|E{self.youngs_modulus_mpa:g}MPa|Y{self.yield_stress_kpa:g}kPa|"
                f"G{self.fracture_toughness_j_m2:g}J/m2|v{self.speed_m_s:g}m/s")


@dataclass(frozen=True)
class Sweep:
    """The grid of samples and the cut every sample shares. Defaults: a ~10-20 min sweep on 2 cores whose
    ranges hold the engine's material presets (E 0.3-3 MPa, yield 50-350 kPa, G_c 50-200 J/m^2) and edges
    of 1.4-6.4 cm (a scale-1 apple's 8 cm is outside: the limiter's out-of-range factor covers it)."""
    speeds_m_s: tuple[float, ...] = log_speeds(0.02, 4.0, 5)
    foods: tuple[str, ...] = ("cucumber", "apple")
    scales: tuple[float, ...] = (0.4, 0.8)
    youngs_modulus_mpa: tuple[float, ...] = (0.1, 1.0, 5.0)
    yield_stress_kpa: tuple[float, ...] = (20.0, 350.0)
    fracture_toughness_j_m2: tuple[float, ...] = (50.0, 600.0)  # spans every preset, the calibrated ones too
    quality: str = "draft"
    # The knife: one vertical cut across the middle, starting just above the food (short cuts).
    knife: dict = field(default_factory=lambda: {"cut_fraction": 0.5, "start_above_top_m": 0.003,
                                                 "end_below_bottom_m": 0.001, "force_window_s": 0.005,
                                                 "lift_speed_m_s": 4.0, "settle_s": 0.0, "max_time_s": 10.0})
    seed: int = 0  # cc-cut's particle sampling jitter

    def samples(self) -> list[Sample]:
        return [Sample(food, scale, e, y, g, v) for food, scale, e, y, g, v in itertools.product(
            self.foods, self.scales, self.youngs_modulus_mpa, self.yield_stress_kpa,
            self.fracture_toughness_j_m2, self.speeds_m_s)]

    def to_json(self) -> dict:
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}

    def scene(self, sample: Sample) -> dict:
        """The cc-cut scene file of one sample (tools/cc_cut/README.md)."""
        overrides = {"youngs_modulus_pa": sample.youngs_modulus_mpa * 1e6,
                     "yield_stress_pa": sample.yield_stress_kpa * 1e3,
                     "fracture_toughness_j_m2": sample.fracture_toughness_j_m2}
        return {"description": f"safety force dataset: {sample.key()}",
                "scene": {"effects": {"mpm": True, "plasticity": True, "damage": True, "friction": True,
                                      "force_sensing": True},
                          "objects": [{"food": sample.food, "scale": sample.scale, "pose": {"position": [0.5, 0.0]},
                                       "material_overrides": overrides}],
                          "quality": self.quality, "seed": self.seed},
                "solver": {"threads": 1},
                "knife": {**self.knife, "descent_speed_m_s": sample.speed_m_s}}


def validate(sweep: Sweep, qualities: list[str]) -> None:
    """Raise ValueError naming the command-line option of the first bad value; `qualities`: the engine's presets."""
    def check(option: str, values, ok, rule: str) -> None:
        if not values:
            raise ValueError(f"{option}: needs at least one value")
        for v in values:
            if not ok(v):
                raise ValueError(f"{option}: {v!r} is not {rule}")
    check("--speeds", sweep.speeds_m_s, lambda v: 0 < v <= MAX_SPEED_M_S, f"in (0, {MAX_SPEED_M_S:g}] m/s")
    check("--foods", sweep.foods, lambda f: f in FOODS, f"one of {', '.join(FOODS)}")
    check("--scales", sweep.scales, lambda s: 0.1 <= s <= 2.0, "in [0.1, 2]")
    check("--youngs-mpa", sweep.youngs_modulus_mpa, lambda e: 0 < e <= 1000, "in (0, 1000] MPa")
    check("--yield-kpa", sweep.yield_stress_kpa, lambda y: 0 <= y <= 1e5, "in [0, 1e5] kPa")
    check("--toughness", sweep.fracture_toughness_j_m2, lambda g: 0 <= g <= 1e4, "in [0, 1e4] J/m^2")
    if sweep.quality not in qualities:
        raise ValueError(f"--quality: {sweep.quality!r} is not one of {', '.join(qualities)}")
