#!/usr/bin/env python3
"""How a step's cost grows with the number of contacts, gymfleet against `mujoco.rollout`
(issue S, item 1). Not a test.

Each scene is `K` free bodies resting on a plane, spaced apart so that they touch only the
floor: spheres (one contact each) or boxes (a face on the floor: four contact points each in
MuJoCo, a contact manifold per box in Rapier). Both sides step the generated MJCF file at
its timestep (2 ms, Euler), five substeps per env step, one thread, as
`rollout_ceiling.py` does (whose two measuring functions this reuses): MuJoCo's
`mujoco.rollout` of `--batch` trajectories, gymfleet's load client in process on one pool
thread. Printed: microseconds per simulated step of one world (an env step is five of
them) on each side, medians of the rounds, the rounds alternating the sides.

    cargo build --release -p gymfleet-load
    pip install mujoco gymnasium
    python bench/peer/contact_scaling.py --rounds 3
"""

from __future__ import annotations

import argparse
import pathlib
import statistics
import tempfile

import mujoco

from rollout_ceiling import gymfleet_rate, mujoco_rate

TIMESTEP = 0.002
FRAME_SKIP = 5


def scene(shape: str, count: int) -> str:
    """MJCF of `count` free `shape`s resting on a plane, 0.3 m apart on a grid."""
    side = max(1, round(count ** 0.5 + 0.4999))
    bodies = []
    for i in range(count):
        x, y = 0.3 * (i % side), 0.3 * (i // side)
        geom = ('<geom type="sphere" size="0.05"/>' if shape == "sphere"
                else '<geom type="box" size="0.05 0.05 0.05"/>')
        bodies.append(f'<body name="b{i}" pos="{x:.2f} {y:.2f} 0.05">'
                      f'<freejoint name="j{i}"/>{geom}</body>')
    return (f'<mujoco model="{shape}s_{count}"><option timestep="{TIMESTEP}"/>'
            '<worldbody><geom name="floor" type="plane" size="20 20 0.1"/>'
            + "".join(bodies) + "</worldbody></mujoco>")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--shapes", nargs="+", default=["sphere", "box"], choices=["sphere", "box"])
    p.add_argument("--counts", nargs="+", type=int, default=[1, 4, 16, 64])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--batch", type=int, default=8, help="trajectories (MuJoCo) and envs (gymfleet)")
    p.add_argument("--seconds-simulated", type=float, default=2.0, help="per MuJoCo trajectory")
    p.add_argument("--duration", type=float, default=2.0, help="gymfleet's timed seconds per round")
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for shape in args.shapes:
            for count in args.counts:
                xml = pathlib.Path(tmp) / f"{shape}s_{count}.xml"
                xml.write_text(scene(shape, count))
                model = mujoco.MjModel.from_xml_path(str(xml))
                data = mujoco.MjData(model)
                for _ in range(200):
                    mujoco.mj_step(model, data)
                ours, theirs = [], []
                for r in range(args.rounds):
                    theirs.append(mujoco_rate(xml, FRAME_SKIP, args.batch, args.seconds_simulated, r))
                    ours.append(gymfleet_rate(xml, FRAME_SKIP, args.batch, args.duration))
                # Simulated seconds per wall second -> microseconds per simulated step.
                a = TIMESTEP / statistics.median(ours) * 1e6
                b = TIMESTEP / statistics.median(theirs) * 1e6
                print(f"{count:3d} {shape}s ({data.ncon:3d} MuJoCo contacts at rest): gymfleet "
                      f"{a:7.2f} µs, mujoco.rollout {b:7.2f} µs per simulated step; "
                      f"ratio {b / a:.2f}", flush=True)


if __name__ == "__main__":
    main()
