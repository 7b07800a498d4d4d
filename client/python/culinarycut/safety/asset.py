"""The force-model asset the server's limiter reads (assets/safety/force_model.json): written from a fit,
read back with the same checks the server makes (a bad field is named)."""
from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from culinarycut.launch import CHECKOUT_ROOT
from culinarycut.safety.posynomial import INPUTS, Posynomial

FORMAT = "culinarycut.safety.force_model"
VERSION = 1
TARGET = "peak_blade_force_n"
OUT_OF_RANGE_FACTOR = 1.5  # outside the data the prediction is scaled up: extrapolation errs on the safe side


def default_model_path() -> Path:
    """Where the server reads its force model: $CULINARYCUT_ASSETS_DIR/safety/force_model.json, else this
    checkout's assets/safety/force_model.json, whatever the working folder."""
    assets = os.environ.get("CULINARYCUT_ASSETS_DIR") or CHECKOUT_ROOT / "assets"
    return Path(assets) / "safety" / "force_model.json"


class AssetError(ValueError):
    """A force-model file the limiter would refuse; the message names the JSON field."""


def build_asset(model: Posynomial, ranges: dict[str, tuple[float, float]], fit: dict, provenance: dict,
                out_of_range_factor: float = OUT_OF_RANGE_FACTOR) -> dict:
    asset = {"format": FORMAT, "version": VERSION, "target": TARGET, "inputs": list(INPUTS),
             "ranges": {name: [float(ranges[name][0]), float(ranges[name][1])] for name in INPUTS},
             "terms": model.terms(), "out_of_range_factor": out_of_range_factor, "fit": fit, "provenance": provenance}
    validate(asset)
    return asset


def write_asset(asset: dict, path: Path) -> None:
    validate(asset)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(asset, indent=1) + "\n")


def _number(value, field: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise AssetError(f"{field}: must be a number")
    if not math.isfinite(value):
        raise AssetError(f"{field}: must be finite")
    return float(value)


def validate(asset: dict) -> None:
    """Raise AssetError naming the first field the server's reader would refuse."""
    if not isinstance(asset, dict):
        raise AssetError("the file must hold a JSON object")
    for name in ("format", "version", "inputs", "ranges", "terms", "out_of_range_factor"):
        if name not in asset:
            raise AssetError(f"{name}: is missing")
    if asset["format"] != FORMAT:
        raise AssetError(f"format: must be {FORMAT!r}, got {asset['format']!r}")
    if asset["version"] != VERSION:
        raise AssetError(f"version: must be {VERSION}, got {asset['version']!r}")
    if asset.get("target", TARGET) != TARGET:
        raise AssetError(f"target: must be {TARGET!r}")
    if list(asset["inputs"]) != list(INPUTS):
        raise AssetError(f"inputs: must be {list(INPUTS)}")
    for name in INPUTS:
        field = f"ranges.{name}"
        pair = asset["ranges"].get(name) if isinstance(asset["ranges"], dict) else None
        if not isinstance(pair, list) or len(pair) != 2:
            raise AssetError(f"{field}: must be [low, high]")
        if _number(pair[0], field + "[0]") > _number(pair[1], field + "[1]"):
            raise AssetError(f"{field}: low is above high")
    if not isinstance(asset["terms"], list) or not asset["terms"]:
        raise AssetError("terms: must be a non-empty array of {coefficient, exponents}")
    for k, term in enumerate(asset["terms"]):
        field = f"terms[{k}]"
        if not isinstance(term, dict) or "coefficient" not in term or "exponents" not in term:
            raise AssetError(f"{field}: must be an object {{coefficient, exponents}}")
        if _number(term["coefficient"], field + ".coefficient") < 0:
            raise AssetError(f"{field}.coefficient: must be >= 0 (the model is a posynomial)")
        if not isinstance(term["exponents"], list) or len(term["exponents"]) != len(INPUTS):
            raise AssetError(f"{field}.exponents: must have {len(INPUTS)} numbers, one per input")
        for j, a in enumerate(term["exponents"]):
            if _number(a, f"{field}.exponents[{j}]") < 0:
                raise AssetError(f"{field}.exponents[{j}]: must be >= 0 (the model is a posynomial)")
    if _number(asset["out_of_range_factor"], "out_of_range_factor") < 1:
        raise AssetError("out_of_range_factor: must be >= 1 (outside the ranges the model is conservative)")


class ForceModel:
    """A validated asset: the posynomial, its ranges and the factor applied outside them."""

    def __init__(self, asset: dict):
        validate(asset)
        self.asset = asset
        self.posynomial = Posynomial(
            coefficients=np.array([t["coefficient"] for t in asset["terms"]], dtype=float),
            exponents=np.array([t["exponents"] for t in asset["terms"]], dtype=float))
        self.ranges = np.array([asset["ranges"][name] for name in INPUTS], dtype=float)
        self.out_of_range_factor = float(asset["out_of_range_factor"])

    @classmethod
    def load(cls, path: Path) -> "ForceModel":
        try:
            return cls(json.loads(Path(path).read_text()))
        except json.JSONDecodeError as err:
            raise AssetError(f"{path}: not JSON ({err})") from None
        except AssetError as err:
            raise AssetError(f"{path}: {err}") from None

    def predict(self, x) -> tuple[float, bool]:
        """(force in N, out of range) at one input vector; outside any range the factor applies, as on the server."""
        x = np.asarray(x, dtype=float)
        outside = bool(np.any((x < self.ranges[:, 0]) | (x > self.ranges[:, 1])))
        force = float(self.posynomial(x[None, :])[0])
        return (force * self.out_of_range_factor if outside else force), outside
