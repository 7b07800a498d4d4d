#!/usr/bin/env python3
"""NVIDIA Warp's CPU backend on the falling-block scene of bench/mpm_falling_block.cc: 3D MLS-MPM (Hu et al. 2018,
MLS-MPM) with quadratic B-splines, APIC/MLS affine momentum, fixed-corotated elasticity (Stomakhin et al. 2012) with
the rotation from wp.svd3, gravity and a frictionless floor at z = 0, float32 like ours; kernels written here. Warp
has no thread setting for the CPU: --threads is recorded, and the JSON's cores_busy says what it used. Prints one
JSON line (falling_block_scene.report). Runs in bench/mpm_peers.py's throwaway virtualenv:

    python bench/peers/warp_falling_block.py --particles 10648 --dx 0.002 --dt 6e-6 ...
"""
from __future__ import annotations

import numpy as np
import warp as wp

from falling_block_scene import Timer, arguments, centre_height, inside_grid, lattice, report, scene

args = arguments(__doc__.strip().splitlines()[0])
s = scene(args)
wp.config.log_level = wp.LOG_WARNING  # stdout carries the JSON line, not the banner and compile times
if args.cache:
    wp.config.kernel_cache_dir = f"{args.cache}/warp"  # compiled kernels stay in the throwaway folder
wp.init()
DEVICE = "cpu"


@wp.func
def spline_weights(fx: float) -> wp.vec3:
    """Quadratic B-spline weights of a particle's three nodes along one axis (fx: its offset from the first, cells)."""
    return wp.vec3(0.5 * (1.5 - fx) * (1.5 - fx), 0.75 - (fx - 1.0) * (fx - 1.0), 0.5 * (fx - 0.5) * (fx - 0.5))


@wp.kernel
def particles_to_grid(x: wp.array(dtype=wp.vec3), v: wp.array(dtype=wp.vec3), C: wp.array(dtype=wp.mat33),
                      F: wp.array(dtype=wp.mat33), grid_v: wp.array3d(dtype=wp.vec3), grid_m: wp.array3d(dtype=float),
                      dx: float, inv_dx: float, pad: int, mass: float, stress_scale: float, mu: float, lam: float):
    p = wp.tid()
    X = x[p] * inv_dx  # cells from world 0, which is node `pad`
    cell = wp.vec3(wp.floor(X[0] - 0.5), wp.floor(X[1] - 0.5), wp.floor(X[2] - 0.5))
    fx = X - cell
    bx = int(cell[0]) + pad
    by = int(cell[1]) + pad
    bz = int(cell[2]) + pad
    wx = spline_weights(fx[0])
    wy = spline_weights(fx[1])
    wz = spline_weights(fx[2])
    Fp = F[p]
    U = wp.mat33()
    sigma = wp.vec3()
    V = wp.mat33()
    wp.svd3(Fp, U, sigma, V)
    R = U @ wp.transpose(V)  # the polar decomposition's rotation
    J = wp.determinant(Fp)
    # Fixed-corotated Kirchhoff stress tau = 2 mu (F - R) F^T + lambda (J - 1) J I, as ours.
    tau = 2.0 * mu * (Fp - R) @ wp.transpose(Fp) + wp.identity(n=3, dtype=float) * (lam * (J - 1.0) * J)
    affine = stress_scale * tau + mass * C[p]
    momentum = mass * v[p]
    for i in range(3):
        for j in range(3):
            for k in range(3):
                dpos = (wp.vec3(float(i), float(j), float(k)) - fx) * dx
                weight = wx[i] * wy[j] * wz[k]
                wp.atomic_add(grid_v, bx + i, by + j, bz + k, weight * (momentum + affine @ dpos))
                wp.atomic_add(grid_m, bx + i, by + j, bz + k, weight * mass)


@wp.kernel
def update_grid(grid_v: wp.array3d(dtype=wp.vec3), grid_m: wp.array3d(dtype=float), dt: float, gravity: float,
                pad: int):
    i, j, k = wp.tid()
    m = grid_m[i, j, k]
    if m > 0.0:
        velocity = grid_v[i, j, k] / m
        vz = velocity[2] - dt * gravity
        # The floor: a node at or below z = 0 stops only the velocity into it (frictionless, like ours).
        if k <= pad and vz < 0.0:
            vz = 0.0
        grid_v[i, j, k] = wp.vec3(velocity[0], velocity[1], vz)


@wp.kernel
def grid_to_particles(x: wp.array(dtype=wp.vec3), v: wp.array(dtype=wp.vec3), C: wp.array(dtype=wp.mat33),
                      F: wp.array(dtype=wp.mat33), grid_v: wp.array3d(dtype=wp.vec3), dx: float, inv_dx: float,
                      pad: int, dt: float):
    p = wp.tid()
    X = x[p] * inv_dx
    cell = wp.vec3(wp.floor(X[0] - 0.5), wp.floor(X[1] - 0.5), wp.floor(X[2] - 0.5))
    fx = X - cell
    bx = int(cell[0]) + pad
    by = int(cell[1]) + pad
    bz = int(cell[2]) + pad
    wx = spline_weights(fx[0])
    wy = spline_weights(fx[1])
    wz = spline_weights(fx[2])
    new_v = wp.vec3()
    new_C = wp.mat33()
    c_scale = 4.0 / (dx * dx)
    for i in range(3):
        for j in range(3):
            for k in range(3):
                dpos = (wp.vec3(float(i), float(j), float(k)) - fx) * dx
                weight = wx[i] * wy[j] * wz[k]
                node_v = grid_v[bx + i, by + j, bz + k]
                new_v += weight * node_v
                new_C += (c_scale * weight) * wp.outer(node_v, dpos)
    v[p] = new_v
    x[p] = x[p] + dt * new_v
    F[p] = (wp.identity(n=3, dtype=float) + dt * new_C) @ F[p]
    C[p] = new_C


n = s.side ** 3
start = lattice(args, s)
x = wp.array(start, dtype=wp.vec3, device=DEVICE)
v = wp.array(np.tile(np.array([0.0, 0.0, -args.drop_speed], np.float32), (n, 1)), dtype=wp.vec3, device=DEVICE)
C = wp.zeros(n, dtype=wp.mat33, device=DEVICE)
F = wp.array(np.tile(np.eye(3, dtype=np.float32), (n, 1, 1)), dtype=wp.mat33, device=DEVICE)
grid_v = wp.zeros(s.grid, dtype=wp.vec3, device=DEVICE)
grid_m = wp.zeros(s.grid, dtype=float, device=DEVICE)
stress_scale = -args.dt * s.particle_volume_m3 * 4.0 / (args.dx * args.dx)  # Hu et al. 2018, eq. 29


def step():
    grid_v.zero_()
    grid_m.zero_()
    wp.launch(particles_to_grid, dim=n, device=DEVICE,
              inputs=[x, v, C, F, grid_v, grid_m, args.dx, 1.0 / args.dx, s.pad, s.particle_mass_kg, stress_scale,
                      s.mu_pa, s.lambda_pa])
    wp.launch(update_grid, dim=s.grid, device=DEVICE, inputs=[grid_v, grid_m, args.dt, args.gravity, s.pad])
    wp.launch(grid_to_particles, dim=n, device=DEVICE,
              inputs=[x, v, C, F, grid_v, args.dx, 1.0 / args.dx, s.pad, args.dt])


for _ in range(args.warmup):
    step()
wp.synchronize_device(DEVICE)
with Timer() as timer:
    for _ in range(args.steps):
        step()
    wp.synchronize_device(DEVICE)
end = x.numpy()
report("warp", wp.__version__, args, timer, centre_height(start) - centre_height(end), inside_grid(end, args, s))
