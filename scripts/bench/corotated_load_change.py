# CPU cost of a step after a traction change against a step without one, co-rotated dynamic grid
# model (docs/cpp-api.md, "Changing loads between steps"): a cube at `resolution`, one V-cycle per step and the
# rotations refreshed every cycle, so that every step costs the same; one thread, process CPU.
# Usage: PYTHONPATH=build/release/python python3 scripts/bench/corotated_load_change.py [resolution]
import sys, time
import mgelastic
res = int(sys.argv[1]) if len(sys.argv) > 1 else 32
quasistatic = False  # quasistatic steps cycle to a tolerance: their costs differ step to step
scene = mgelastic.Scene.from_dict({
    "engine": "grid", "geometry": {"box": {"size": [1, 1, 1]}}, "grid": {"resolution": res},
    "material": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000, "model": "corotated"},
    "constraints": [{"region": {"box": {"center": [0, -0.5, 0], "size": [1.2, 0.1, 1.2]}}}],
    "loads": {"gravity": [0, 0, 0], "tractions": [{"region": {"box": {"center": [0, 0.5, 0], "size": [1.2, 0.1, 1.2]}},
                                                     "normal": [0, 1, 0], "traction": [100, 0, 0]}]},
    "time": {"dt": 0.01, "frames": 100, "quasistatic": quasistatic, "vcycles_per_step": 1, "rotation_update_every": 1},
    "solver": {"precision": "double", "tolerance": 1e-30, "max_vcycles": 2},
    "output": {"formats": []}})
t = time.process_time()
sim = mgelastic.Simulation(scene, threads=1)
build = time.process_time() - t
def cpu_step():
    t = time.process_time()
    sim.step()
    return time.process_time() - t
cpu_step()
plain = [cpu_step() for _ in range(3)]
changed = []
for k in range(3):
    sim.set_traction(0, (100 + 50 * (k + 1), 0, 0))
    changed.append(cpu_step())
    plain.append(cpu_step())
print(f"res {res} {'quasistatic' if quasistatic else 'dynamic'} corotated: build {build:.2f} s CPU; "
      f"step {min(plain):.3f}-{max(plain):.3f} s; step after a load change "
      f"{min(changed):.3f}-{max(changed):.3f} s (CPU, threads=1)")
