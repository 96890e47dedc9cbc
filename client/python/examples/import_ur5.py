"""Bring a real robot in: Universal Robots' UR5 from its ROS description (URDF) and its STL
collision meshes, as example-robot-data ships them (a copy lives in this repository's test
data), driven with position targets.

    python client/python/examples/import_ur5.py [--urdf PATH --assets FOLDER] [--steps N]

The server converts the URDF (each mesh becomes its convex hull, read from the assets),
builds the env, and the arm moves to a target pose and holds it against gravity. What the
conversion ignored is printed first; `gymfleet.convert` shows the JSON it built.
"""

from __future__ import annotations

import argparse
import pathlib

import numpy as np

import gymfleet

REPO = pathlib.Path(__file__).resolve().parents[3]
DATA = REPO / "crates" / "import" / "tests" / "data"
UR5 = DATA / "example-robot-data" / "robots" / "ur_description" / "urdf" / "ur5_robot.urdf"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--urdf", default=str(UR5), help="the URDF file")
    parser.add_argument("--assets", default=str(DATA), help="the folder (or zip/tar) its meshes resolve against")
    parser.add_argument("--steps", type=int, default=480, help="env steps (1/240 s each)")
    args = parser.parse_args()

    document, warnings = gymfleet.convert(args.urdf, assets=args.assets)
    print(f"converted: {len(document['assembly']['instances'])} instances, "
          f"{sum(j['type'] != 'fixed' for j in document['assembly']['joints'])} moving joints")
    for warning in warnings:
        print(f"  ignored: {warning}")

    env = gymfleet.make(args.urdf, assets=args.assets, action_type="position", end_effector_ids=["ee_link"])
    names = [j["name"] for j in env.env_info["joints"]]
    obs, _ = env.reset(seed=0)
    n = len(names)
    print(f"joints: {', '.join(names)}")
    print(f"start: tool at {np.round(obs[2 * n:2 * n + 3], 1)} mm")

    # Lift the upper arm 30°, bend the elbow 60°, turn the base 45° (targets in degrees).
    target = np.zeros(n, dtype=np.float32)
    target[names.index("shoulder_pan_joint")] = 45.0
    target[names.index("shoulder_lift_joint")] = -30.0
    target[names.index("elbow_joint")] = 60.0
    for _ in range(args.steps):
        obs, *_ = env.step(target)
    error = np.abs(obs[:n] - target).max()
    print(f"after {args.steps} steps: joints {np.round(obs[:n], 2)} deg (largest error {error:.2f} deg), "
          f"tool at {np.round(obs[2 * n:2 * n + 3], 1)} mm")
    env.close()


if __name__ == "__main__":
    main()
