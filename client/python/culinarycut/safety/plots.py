"""Pictures of a fit: predicted against measured peak force, and force against knife speed per material."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from culinarycut.safety.fit import FitResult
from culinarycut.safety.posynomial import INPUTS, SPEED

MAX_PANELS = 6


def plot_fit(result: FitResult, x: np.ndarray, y: np.ndarray, rows: list[dict], directory: Path) -> list[Path]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    written = []

    predicted = result.model(x)
    held = np.zeros(len(y), dtype=bool)
    held[result.held_out_rows] = True
    fig, ax = plt.subplots(figsize=(4.6, 4.4))
    ax.scatter(y[~held], predicted[~held], s=12, color="0.65", label=f"training ({int((~held).sum())})")
    ax.scatter(y[held], predicted[held], s=16, color="tab:red", label=f"held out ({int(held.sum())})")
    top = 1.05 * max(y.max(), predicted.max())
    ax.plot([0, top], [0, top], "k--", lw=0.8)
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel("measured peak blade force, 5 ms window (N)")
    ax.set_ylabel("predicted F_hat (N)")
    ax.set_title(f"held out: R^2 {result.held_out['r2']:.3f}, RMSE {result.held_out['rmse_n']:.2f} N", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    written.append(directory / "safety_force_predicted_vs_measured.png")
    fig.savefig(written[-1], dpi=110)
    plt.close(fig)

    # Force against speed: one panel per food and scale, one colour per (E, G_c), at the first yield stress.
    foods = sorted({(r["food"], r["scale"]) for r in rows})[:MAX_PANELS]
    first_yield = min(r["yield_stress_kpa"] for r in rows)
    fig, axes = plt.subplots(1, len(foods), figsize=(3.6 * len(foods), 3.4), sharey=True, squeeze=False)
    speeds = np.geomspace(x[:, SPEED].min(), x[:, SPEED].max(), 100)
    for ax, (food, scale) in zip(axes[0], foods):
        chosen = [i for i, r in enumerate(rows) if (r["food"], r["scale"]) == (food, scale)
                  and r["yield_stress_kpa"] == first_yield]
        materials = sorted({(rows[i]["youngs_modulus_mpa"], rows[i]["fracture_toughness_j_m2"]) for i in chosen})
        for colour, (e_mpa, g) in zip(plt.cm.viridis(np.linspace(0, 0.9, len(materials))), materials):
            mine = [i for i in chosen if (rows[i]["youngs_modulus_mpa"], rows[i]["fracture_toughness_j_m2"]) == (e_mpa, g)]
            ax.plot(x[mine, SPEED], y[mine], "o", color=colour, ms=4, label=f"E {e_mpa:g} MPa, G_c {g:g} J/m^2")
            curve = np.repeat(x[mine[0]][None, :], len(speeds), axis=0)
            curve[:, SPEED] = speeds
            ax.plot(speeds, result.model(curve), "-", color=colour, lw=1)
        ax.set_xscale("log")
        ax.set_title(f"{food}, scale {scale:g} (edge {x[chosen[0], INPUTS.index('edge_length_m')] * 1e3:.0f} mm)",
                     fontsize=9)
        ax.set_xlabel("knife speed (m/s)")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel(f"peak blade force (N), yield {first_yield:g} kPa")
    axes[0][-1].legend(fontsize=7)
    fig.tight_layout()
    written.append(directory / "safety_force_vs_speed.png")
    fig.savefig(written[-1], dpi=110)
    plt.close(fig)
    return written
