#!/usr/bin/env python3
"""What kinematic loops cost (issue X): per env step, one thread, gymfleet against MuJoCo on
the same MJCF files, and each closed mechanism against the open tree of the same bodies.

Models (written below, MJCF, passive, swinging under gravity from their model pose):
- `fourbar`: a crank-rocker four-bar (crank 40 mm, coupler 120, rocker 100, ground 110),
  its loop closed by one `<connect>` (3 tree DOFs, 1 loop);
- `platform6`: a platform hung from the ground by seven parallel legs (a planar parallel
  swing: the first leg carries the platform in the tree, the six others close loops with
  `<connect>`s; 8 tree DOFs, 6 loops, 1 DOF of motion).
Each also runs "open": the same file without its `<equality>` (the same tree, no loops).

gymfleet converts each file itself (`convert` example) and steps it with `peer_step`
(`--variant zero --substeps 1 --dt 0.001`: one Euler step of MuJoCo's 1 ms timestep per env
step); MuJoCo times `mj_step` on the same file. The two sides alternate `--rounds` times;
the medians and their ratio are printed.

Setup (not part of CI): `cargo build --release -p gymfleet-env -p gymfleet-import --example
peer_step --example convert`, and a Python with `mujoco`:
  python3 bench/peer/loops_bench.py --rounds 5
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import tempfile
import time

import mujoco

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
RELEASE = os.path.join(ROOT, "target", "release", "examples")
RESET_EVERY = 1000


def capsule(p, q, r=0.004):
    return (f'<geom type="capsule" fromto="{p[0]} 0 {p[1]} {q[0]} 0 {q[1]}" size="{r}" '
            'contype="0" conaffinity="0"/>')


def fourbar() -> str:
    a, b, c, d = 0.04, 0.12, 0.10, 0.11
    t = math.radians(60)
    ax, az = a * math.cos(t), a * math.sin(t)
    dx, dz = d - ax, -az
    dist = math.hypot(dx, dz)
    along = (b * b - c * c + dist * dist) / (2 * dist)
    across = math.sqrt(b * b - along * along)
    bx = ax + (along * dx - across * dz) / dist
    bz = az + (along * dz + across * dx) / dist
    return f"""<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <body name="crank">
      <joint name="crank" type="hinge" axis="0 -1 0"/>
      {capsule((0, 0), (ax, az))}
      <body name="coupler" pos="{ax} 0 {az}">
        <joint name="elbow" type="hinge" axis="0 -1 0"/>
        {capsule((0, 0), (bx - ax, bz - az))}
      </body>
    </body>
    <body name="rocker" pos="{d} 0 0">
      <joint name="rocker" type="hinge" axis="0 -1 0"/>
      {capsule((0, 0), (bx - d, bz))}
    </body>
  </worldbody>
  <equality>
    <connect body1="coupler" body2="rocker" anchor="{bx - ax} 0 {bz - az}"/>
  </equality>
</mujoco>"""


def platform6() -> str:
    legs, spacing, length, tilt = 7, 0.05, 0.15, math.radians(30)
    lx, lz = length * math.sin(tilt), -length * math.cos(tilt)
    bodies, equalities = [], []
    for k in range(legs):
        x = k * spacing
        platform = ""
        if k == 0:
            platform = f"""
        <body name="platform" pos="{lx} 0 {lz}">
          <joint name="carry" type="hinge" axis="0 1 0"/>
          {capsule((0, 0), ((legs - 1) * spacing, 0), 0.006)}
        </body>"""
        bodies.append(f"""
    <body name="leg{k}" pos="{x} 0 0">
      <joint name="swing{k}" type="hinge" axis="0 1 0"/>
      {capsule((0, 0), (lx, lz))}{platform}
    </body>""")
        if k > 0:
            equalities.append(
                f'<connect body1="platform" body2="leg{k}" anchor="{x} 0 0"/>')
    return f"""<mujoco>
  <option timestep="0.001"/>
  <worldbody>{''.join(bodies)}
  </worldbody>
  <equality>
    {chr(10).join(equalities)}
  </equality>
</mujoco>"""


def open_variant(xml: str) -> str:
    start, end = xml.index("<equality>"), xml.index("</equality>") + len("</equality>")
    return xml[:start] + xml[end:]


def gymfleet_us(xml: str, steps: int, repeats: int, work: str, name: str) -> float:
    path = os.path.join(work, name + ".xml")
    with open(path, "w") as f:
        f.write(xml)
    doc = os.path.join(work, name + ".json")
    with open(doc, "w") as f:
        f.write(subprocess.run([os.path.join(RELEASE, "convert"), path], check=True,
                               capture_output=True, text=True).stdout)
    observed = json.load(open(doc))["assembly"]["instances"][-1]["name"]
    cmd = [os.path.join(RELEASE, "peer_step"), "--document", doc, "--end-effector", observed,
           "--substeps", "1", "--dt", "0.001", "--variant", "zero", "--steps", str(steps),
           "--repeats", str(repeats)]
    out = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    return out["us_per_env_step"]


def mujoco_us(xml: str, steps: int, repeats: int) -> float:
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    best = []
    for _ in range(repeats):
        mujoco.mj_resetData(m, d)
        start = time.perf_counter()
        for i in range(steps):
            if i % RESET_EVERY == 0:
                mujoco.mj_resetData(m, d)
            mujoco.mj_step(m, d)
        best.append((time.perf_counter() - start) / steps * 1e6)
    return statistics.median(best)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--steps", type=int, default=4000)
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    print(f"mujoco {mujoco.__version__}; 1 ms Euler step, one thread; median of {args.rounds} "
          f"alternating rounds x {args.repeats} repeats x {args.steps} steps")
    print(f"{'model':<18}{'gymfleet us':>12}{'mujoco us':>11}{'ratio':>8}")
    rows = {}
    with tempfile.TemporaryDirectory() as work:
        for name, xml in [("fourbar", fourbar()), ("platform6", platform6())]:
            for variant, text in [("closed", xml), ("open", open_variant(xml))]:
                ours, theirs = [], []
                for _ in range(args.rounds):
                    ours.append(gymfleet_us(text, args.steps, args.repeats, work,
                                            f"{name}_{variant}"))
                    theirs.append(mujoco_us(text, args.steps, args.repeats))
                g, m = statistics.median(ours), statistics.median(theirs)
                rows[(name, variant)] = (g, m)
                print(f"{name + ' ' + variant:<18}{g:>12.2f}{m:>11.2f}{g / m:>8.2f}")
    for name in ("fourbar", "platform6"):
        (gc, mc), (go, mo) = rows[(name, "closed")], rows[(name, "open")]
        print(f"{name}: the loops cost {gc / go:.2f}x the open tree here, {mc / mo:.2f}x in MuJoCo")


if __name__ == "__main__":
    main()
