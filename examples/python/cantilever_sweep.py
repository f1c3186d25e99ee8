#!/usr/bin/env python3
"""Tip deflection of a clamped cantilever under gravity as the Poisson ratio sweeps towards the
incompressible limit, plotted with matplotlib against Euler-Bernoulli beam theory.

    PYTHONPATH=build/release/python python3 examples/python/cantilever_sweep.py
    ... --resolution 8 --output /tmp/sweep.png     (small and fast)
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt

import mgelastic

LENGTH, SIDE, YOUNG, DENSITY, G = 1.0, 0.1, 1e7, 1000.0, 9.81


def scene(poisson_ratio, resolution):
    return mgelastic.Scene.from_dict({
        "engine": "grid",
        "geometry": {"box": {"center": [LENGTH / 2, 0, 0], "size": [LENGTH, SIDE, SIDE]}},
        "grid": {"resolution": resolution},
        "material": {"youngs_modulus": YOUNG, "poisson_ratio": poisson_ratio, "density": DENSITY},
        "constraints": [{"region": {"box": {"center": [0, 0, 0], "size": [0.04, 0.2, 0.2]}}}],
        "loads": {"gravity": [0, -G, 0]},
        "solver": {"tolerance": 1e-8, "max_vcycles": 60, "precision": "double"},
    }, name=f"cantilever nu={poisson_ratio}")


def tip_deflection(poisson_ratio, resolution, threads):
    sim = mgelastic.Simulation(scene(poisson_ratio, resolution), threads=threads)
    vertices, _ = sim.surface()  # (V, 3) m, a live view of the deformed surface
    rest = vertices.copy()
    sim.step()  # quasistatic: one equilibrium
    tip = rest[:, 0] > rest[:, 0].max() - 0.02 * LENGTH  # the free end's surface vertices
    return -(vertices[tip, 1] - rest[tip, 1]).mean()  # their mean vertical deflection, m


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--resolution", type=int, default=48, help="cells along the beam")
    parser.add_argument("--threads", type=int, default=0, help="0 = all cores")
    parser.add_argument("--output", default="cantilever_sweep.png")
    args = parser.parse_args()

    ratios = [0.0, 0.1, 0.2, 0.3, 0.4, 0.45, 0.49]
    deflections = []
    for nu in ratios:
        deflections.append(tip_deflection(nu, args.resolution, args.threads))
        print(f"nu = {nu:4.2f}: tip deflection {deflections[-1] * 1e3:8.3f} mm")
    # Euler-Bernoulli: w = q L^4 / (8 E I), q = rho g A, I = a^4 / 12 (independent of nu).
    beam = DENSITY * G * SIDE**2 * LENGTH**4 / (8 * YOUNG * SIDE**4 / 12)

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(ratios, [d * 1e3 for d in deflections], "o-", label=f"mgelastic grid, {args.resolution} cells")
    ax.axhline(beam * 1e3, color="gray", linestyle="--", label="Euler-Bernoulli beam")
    ax.set_xlabel("Poisson ratio")
    ax.set_ylabel("tip deflection (mm)")
    ax.set_title("Cantilever under gravity, E = 10 MPa")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
