#!/usr/bin/env python3
"""Taichi's CPU backend on the falling-block scene of bench/mpm_falling_block.cc: 3D MLS-MPM (Hu et al. 2018,
MLS-MPM; the structure of Taichi's mpm99 example, written again here in 3D) with quadratic B-splines, APIC/MLS affine
momentum, fixed-corotated elasticity (Stomakhin et al. 2012) by polar decomposition, gravity and a frictionless floor
at z = 0, float32 like ours. Prints one JSON line (falling_block_scene.report). Runs in bench/mpm_peers.py's
throwaway virtualenv:

    python bench/peers/taichi_falling_block.py --particles 10648 --threads 1 --dx 0.002 --dt 6e-6 ...
"""
from __future__ import annotations

import numpy as np
import taichi as ti

from falling_block_scene import Timer, arguments, centre_height, inside_grid, lattice, report, scene

args = arguments(__doc__.strip().splitlines()[0])
s = scene(args)
# Compiled kernels only into the throwaway folder (--cache), if any; the warm-up steps take the compile time.
cache = {"offline_cache": True, "offline_cache_file_path": f"{args.cache}/taichi"} if args.cache else \
    {"offline_cache": False}
ti.init(arch=ti.cpu, cpu_max_num_threads=args.threads, default_fp=ti.f32, log_level=ti.WARN, **cache)

n = s.side ** 3
dx, inv_dx, dt = args.dx, 1.0 / args.dx, args.dt
mass, volume = s.particle_mass_kg, s.particle_volume_m3
mu, lam, gravity, pad = s.mu_pa, s.lambda_pa, args.gravity, s.pad
stress_scale = -dt * volume * 4.0 * inv_dx * inv_dx  # the MLS-MPM stress term's factor (Hu et al. 2018, eq. 29)

x = ti.Vector.field(3, ti.f32, n)       # m, world frame
v = ti.Vector.field(3, ti.f32, n)       # m/s
C = ti.Matrix.field(3, 3, ti.f32, n)    # affine velocity field, 1/s
F = ti.Matrix.field(3, 3, ti.f32, n)    # deformation gradient
grid_v = ti.Vector.field(3, ti.f32, s.grid)  # momentum after P2G, velocity after the grid update
grid_m = ti.field(ti.f32, s.grid)


@ti.kernel
def clear_grid():
    for I in ti.grouped(grid_m):
        grid_v[I] = ti.Vector.zero(ti.f32, 3)
        grid_m[I] = 0.0


@ti.kernel
def particles_to_grid():
    for p in x:
        X = x[p] * inv_dx  # cells from world 0, which is node `pad`
        cell = ti.cast(ti.floor(X - 0.5), ti.i32)
        fx = X - cell
        base = cell + pad
        w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
        R, _ = ti.polar_decompose(F[p])
        J = F[p].determinant()
        # Fixed-corotated Kirchhoff stress tau = 2 mu (F - R) F^T + lambda (J - 1) J I, as ours.
        tau = 2.0 * mu * (F[p] - R) @ F[p].transpose() + ti.Matrix.identity(ti.f32, 3) * lam * (J - 1.0) * J
        affine = stress_scale * tau + mass * C[p]
        for i, j, k in ti.static(ti.ndrange(3, 3, 3)):
            offset = ti.Vector([i, j, k])
            dpos = (offset - fx) * dx
            weight = w[i][0] * w[j][1] * w[k][2]
            grid_v[base + offset] += weight * (mass * v[p] + affine @ dpos)
            grid_m[base + offset] += weight * mass


@ti.kernel
def update_grid():
    for I in ti.grouped(grid_m):
        if grid_m[I] > 0:
            velocity = grid_v[I] / grid_m[I]
            velocity[2] -= dt * gravity
            # The floor: a node at or below z = 0 stops only the velocity into it (frictionless, like ours).
            if I[2] <= pad and velocity[2] < 0:
                velocity[2] = 0.0
            grid_v[I] = velocity


@ti.kernel
def grid_to_particles():
    for p in x:
        X = x[p] * inv_dx
        cell = ti.cast(ti.floor(X - 0.5), ti.i32)
        fx = X - cell
        base = cell + pad
        w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
        new_v = ti.Vector.zero(ti.f32, 3)
        new_C = ti.Matrix.zero(ti.f32, 3, 3)
        for i, j, k in ti.static(ti.ndrange(3, 3, 3)):
            offset = ti.Vector([i, j, k])
            dpos = (offset - fx) * dx
            weight = w[i][0] * w[j][1] * w[k][2]
            node_v = grid_v[base + offset]
            new_v += weight * node_v
            new_C += 4.0 * inv_dx * inv_dx * weight * node_v.outer_product(dpos)
        v[p] = new_v
        x[p] += dt * new_v
        F[p] = (ti.Matrix.identity(ti.f32, 3) + dt * new_C) @ F[p]
        C[p] = new_C


def step():
    clear_grid()
    particles_to_grid()
    update_grid()
    grid_to_particles()


start = lattice(args, s)
x.from_numpy(start)
v.from_numpy(np.tile(np.array([0.0, 0.0, -args.drop_speed], np.float32), (n, 1)))
F.from_numpy(np.tile(np.eye(3, dtype=np.float32), (n, 1, 1)))
C.from_numpy(np.zeros((n, 3, 3), np.float32))
for _ in range(args.warmup):
    step()
ti.sync()
with Timer() as timer:
    for _ in range(args.steps):
        step()
    ti.sync()
end = x.to_numpy()
report("taichi", ".".join(map(str, ti.__version__)), args, timer, centre_height(start) - centre_height(end),
       inside_grid(end, args, s))
