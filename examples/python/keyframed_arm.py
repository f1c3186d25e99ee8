#!/usr/bin/env python3
"""The skeleton arm (examples/scenes/skeleton_arm.json) with its forearm bone driven from Python:
every frame the bone's pose about the elbow is set from a script instead of the scene's
keyframes, and the hand's position is read back from the deformed surface.

    PYTHONPATH=build/release/python python3 examples/python/keyframed_arm.py
    ... --resolution 16 --frames 6      (small and fast)
"""
import argparse
import math
import pathlib

import numpy as np

import mgelastic

SCENE = pathlib.Path(__file__).resolve().parents[1] / "scenes" / "skeleton_arm.json"
FOREARM = 1  # index of the keyframed constraint region in the scene


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--resolution", type=int, default=64)
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--threads", type=int, default=0, help="0 = all cores")
    args = parser.parse_args()

    document = mgelastic.Scene.load(SCENE).to_dict()
    document["grid"]["resolution"] = args.resolution
    document["time"]["frames"] = args.frames
    sim = mgelastic.Simulation(mgelastic.Scene.from_dict(document, directory=SCENE.parent),
                               threads=args.threads)

    vertices, _ = sim.surface()  # a live view: refreshed after every step
    hand = int(np.argmax(vertices[:, 0]))  # the rest surface vertex farthest along the arm
    period = 1.0  # s: one wave of the forearm
    while sim.frame < sim.frames:
        t = (sim.frame + 1) * sim.scene.dt  # the time of the frame about to be computed
        angle = 60.0 * math.sin(2 * math.pi * t / period)
        lift = (0.0, 0.02 * (1 - math.cos(2 * math.pi * t / period)), 0.0)
        sim.set_region_pose(FOREARM, translate=lift, rotate=mgelastic.rotation([0, 0, 1], angle))
        stats = sim.step()
        x, y, z = vertices[hand]
        print(f"frame {stats.frame:3d} t={stats.time:5.3f} s  elbow {angle:6.1f} deg  "
              f"hand at ({x:+.3f}, {y:+.3f}, {z:+.3f}) m  cycles {stats.cycles}")


if __name__ == "__main__":
    main()
