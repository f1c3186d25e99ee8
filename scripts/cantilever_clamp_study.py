#!/usr/bin/python3
"""Where the grid engine's cantilever clamp sits (docs/validation.md, "Cantilever").

    scripts/cantilever_clamp_study.py [--mgelastic build/release/app/mgelastic] [n ...]

Runs the validation cantilever (1 x 0.2 x 0.2 m, E 1e6 Pa, nu 0.3, 10 N tip force on the face
x = 1 m) with `mgelastic run` at n cells along the bar (default 20 40 80 160), clamped two ways:

* first_layer: the body [0, L] and the constraint slab |x| < 0.6 h, which takes the whole first
  body cell (a Dirichlet cell is a whole cell): the bench's clamp before 2026-12-04.
* wall: the body continues behind the wall x = 0 and the constraint takes exactly the cells
  there, so the free length is L at every resolution (the bench's clamp now).

Prints the tip deflection (mean of 5 x 5 probes on the tip face), its error against Timoshenko,
and the first-layer value divided by the wall value times ((L - h) / L)^3, i.e. by the wall
clamp's deflection of a bar one cell shorter, in the bending-dominated approximation.
"""
import argparse
import csv
import json
import subprocess
import tempfile
from pathlib import Path

L, T, P, E, NU = 1.0, 0.2, 10.0, 1e6, 0.3


def timoshenko():
    i, a, g = T**4 / 12, T * T, E / (2 * (1 + NU))
    kappa = 10 * (1 + NU) / (12 + 11 * NU)
    return P * L**3 / (3 * E * i) + P * L / (kappa * g * a)


def scene(clamp, n):
    h, mid = L / n, T / 2
    if clamp == "first_layer":
        start, low, high = 0.0, -0.6 * h, 0.6 * h
    else:
        start, low, high = -h, -2 * h, 0.01 * h

    def box(lo, hi, size):
        return {"box": {"center": [(lo + hi) / 2, mid, mid], "size": [hi - lo, size, size]}}

    probes = [{"name": f"p{i}{j}", "point": [L - 1e-9, T * (i + 0.5) / 5, T * (j + 0.5) / 5]}
              for i in range(5) for j in range(5)]
    return {"engine": "grid", "geometry": box(start, L, T), "grid": {"cell_size": h},
            "material": {"youngs_modulus": E, "poisson_ratio": NU, "density": 100},
            "constraints": [{"region": box(low, high, 2 * T)}],
            "loads": {"gravity": [0, 0, 0],
                      "forces": [{"region": box(0.95 * L, 1.05 * L, 2 * T), "normal": [1, 0, 0],
                                  "force": [0, -P, 0]}]},
            "time": {"quasistatic": True, "frames": 1},
            "solver": {"tolerance": 1e-9, "max_vcycles": 200, "precision": "double"},
            "output": {"formats": [], "probes": probes}}


def tip_deflection(mgelastic, clamp, n, work):
    folder = work / f"{clamp}_{n}"
    folder.mkdir()
    (folder / "scene.json").write_text(json.dumps(scene(clamp, n)))
    subprocess.run([mgelastic, "run", str(folder / "scene.json"), "--output", str(folder)],
                   check=True, capture_output=True)
    row = list(csv.DictReader(open(folder / "probes.csv")))[-1]
    return -sum(float(row[f"p{i}{j}.uy"]) for i in range(5) for j in range(5)) / 25


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mgelastic", default="build/release/app/mgelastic")
    parser.add_argument("n", nargs="*", type=int, default=[20, 40, 80, 160])
    args = parser.parse_args()
    reference = timoshenko()
    print(f"Timoshenko: {reference:.6e} m")
    print("    n   first_layer   error      wall          error    "
          "first_layer / (wall (1 - h/L)^3)")
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.n:
            first = tip_deflection(args.mgelastic, "first_layer", n, Path(tmp))
            wall = tip_deflection(args.mgelastic, "wall", n, Path(tmp))
            shorter = wall * (1 - 1 / n) ** 3
            print(f"{n:5d}  {first:.6e}  {100 * (first / reference - 1):+6.2f} %  {wall:.6e}  "
                  f"{100 * (wall / reference - 1):+6.2f} %  {first / shorter:.4f}", flush=True)


if __name__ == "__main__":
    main()
