"""The falling-block scene both peers simulate, as bench/mpm_falling_block.cc builds it for ours: its command-line
settings (bench/mpm_peers.py passes ours on), the particles' starting lattice, the dense grid that covers the
block's fall, and the one JSON line each peer prints. Runs inside the peers' throwaway virtualenv: NumPy only."""
from __future__ import annotations

import argparse
import json
import time
from dataclasses import dataclass

import numpy as np

LATTICE_PER_CELL_AXIS = 2  # 2 x 2 x 2 = 8 particles per cell, as ours
PAD_CELLS = 3  # empty cells around the block's path: the stencil reaches 2, the block's bulge on landing less than 1


def arguments(description: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--particles", type=int, required=True, help="a cube's count (side^3), as ours reports it")
    parser.add_argument("--threads", type=int, default=1, help="CPU threads the peer may use")
    parser.add_argument("--dx", type=float, required=True, help="grid spacing, m")
    parser.add_argument("--dt", type=float, required=True, help="time step, s (ours: the CFL step)")
    parser.add_argument("--youngs", type=float, required=True, help="Young's modulus E, Pa")
    parser.add_argument("--poisson", type=float, required=True, help="Poisson's ratio nu")
    parser.add_argument("--density", type=float, required=True, help="density rho, kg/m^3")
    parser.add_argument("--gravity", type=float, default=9.81, help="downward acceleration, m/s^2")
    parser.add_argument("--gap", type=float, required=True, help="the block's underside above the floor, m")
    parser.add_argument("--drop-speed", type=float, required=True, help="the block's starting downward speed, m/s")
    parser.add_argument("--steps", type=int, required=True, help="timed steps")
    parser.add_argument("--warmup", type=int, default=3, help="steps before the timing (kernels compile on the first)")
    parser.add_argument("--cache", default=None, help="folder for compiled kernels (Taichi: none kept without it)")
    return parser.parse_args()


@dataclass(frozen=True)
class Scene:
    side: int                # particles per side of the cube
    spacing_m: float         # lattice spacing, dx / 2
    grid: tuple[int, int, int]  # dense grid nodes per axis
    pad: int                 # node index of world coordinate 0 on every axis (the floor is the plane k = pad)
    mu_pa: float             # Lame parameters of E, nu
    lambda_pa: float
    particle_mass_kg: float
    particle_volume_m3: float


def scene(args: argparse.Namespace) -> Scene:
    side = round(args.particles ** (1 / 3))
    if side ** 3 != args.particles:
        raise SystemExit(f"error: --particles {args.particles} is no cube (ours reports side^3)")
    spacing = args.dx / LATTICE_PER_CELL_AXIS
    length_cells = int(np.ceil(side * spacing / args.dx))
    height_cells = int(np.ceil((args.gap + side * spacing) / args.dx))
    grid = (length_cells + 2 * PAD_CELLS + 1, length_cells + 2 * PAD_CELLS + 1, height_cells + 2 * PAD_CELLS + 1)
    volume = spacing ** 3
    E, nu = args.youngs, args.poisson
    return Scene(side=side, spacing_m=spacing, grid=grid, pad=PAD_CELLS, mu_pa=E / (2 * (1 + nu)),
                 lambda_pa=E * nu / ((1 + nu) * (1 - 2 * nu)),
                 particle_mass_kg=float(np.float32(args.density * volume)), particle_volume_m3=float(np.float32(volume)))


def lattice(args: argparse.Namespace, s: Scene) -> np.ndarray:
    """The starting positions (n x 3, float32, m) in ours' order and rounding: computed in double, then rounded."""
    centres = (np.arange(s.side) + 0.5) * s.spacing_m
    i, j, k = np.meshgrid(centres, centres, centres, indexing="ij")
    return np.stack([i.ravel(), j.ravel(), args.gap + k.ravel()], axis=1).astype(np.float32)


def centre_height(positions: np.ndarray) -> float:
    """The centre of mass's height (m): every particle has the same mass."""
    return float(np.mean(positions[:, 2], dtype=np.float64))


def inside_grid(positions: np.ndarray, args: argparse.Namespace, s: Scene) -> bool:
    """Whether every particle's stencil still lies in the dense grid (else the run measured nothing valid)."""
    base = np.floor(positions / args.dx + s.pad - 0.5)
    return bool(np.all(base >= 0) and np.all(base + 2 < np.array(s.grid)))


class Timer:
    """Wall and process CPU time of the timed steps: CPU over wall is how many cores the peer kept busy."""

    def __enter__(self) -> "Timer":
        self.wall, self.cpu = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc) -> None:
        self.wall, self.cpu = time.perf_counter() - self.wall, time.process_time() - self.cpu


def report(peer: str, version: str, args: argparse.Namespace, timer: Timer, drop_m: float, ok: bool) -> None:
    """The one JSON line bench/mpm_peers.py reads (the last line of stdout that starts with "{")."""
    print(json.dumps({"peer": peer, "version": version, "threads": args.threads, "particles": args.particles,
                      "steps": args.steps, "seconds": timer.wall,
                      "particle_steps_per_s": args.particles * args.steps / timer.wall,
                      "cores_busy": timer.cpu / timer.wall, "com_drop_m": drop_m, "inside_grid": ok}), flush=True)
