#!/usr/bin/env python3
"""How far HalfCheetah drifts under random actions, on MuJoCo with its file's soft contacts,
on MuJoCo with them made stiff, and on gymfleet (issue L3: why gymfleet's HalfCheetah
learns slower). Not a test.

Gymnasium's ``half_cheetah.xml`` gives every geom ``solimp="0.0 0.8 0.01"``: a contact's
impedance starts at 0 at zero penetration and reaches 0.8 only 1 cm deep, far softer than
MuJoCo's own default (``0.9 0.95 0.001``); its joint limits are as soft
(``solimplimit="0 .8 .03"``). gymfleet's contacts and limits were rigid (Rapier) until issue
C; since vendored Rapier patches 43 and 44 they are MuJoCo's, ``solimp`` and all. Each variant: EPISODES episodes of 1000 steps of uniform random actions (the same
action stream on every side, ``reset(seed=k)``), the root's x at the end, mean ± sd.

    python bench/python/contact_softness_probe.py --episodes 20
    python bench/python/contact_softness_probe.py --write-stiff target/half_cheetah_stiff.xml
"""

from __future__ import annotations

import argparse
import pathlib
import tempfile
from typing import Dict

import gymnasium as gym
import numpy as np

SOFT_CONTACTS = 'solimp="0.0 0.8 0.01"'
SOFT_LIMITS = 'solimplimit="0 .8 .03"'
STIFF = "0.9 0.95 0.001"  # MuJoCo's default solimp


def variants() -> Dict[str, str]:
    src = (pathlib.Path(gym.__file__).parent / "envs/mujoco/assets/half_cheetah.xml").read_text()
    assert SOFT_CONTACTS in src and SOFT_LIMITS in src, "Gymnasium's half_cheetah.xml changed"
    contacts = src.replace(SOFT_CONTACTS, f'solimp="{STIFF}"')
    return {
        "as the file says": src,
        "stiff contacts": contacts,
        "stiff limits": src.replace(SOFT_LIMITS, f'solimplimit="{STIFF}"'),
        "stiff both": contacts.replace(SOFT_LIMITS, f'solimplimit="{STIFF}"'),
    }


def drift(env_id: str, xml: str, episodes: int) -> np.ndarray:
    path = pathlib.Path(tempfile.mkdtemp()) / "half_cheetah.xml"
    path.write_text(xml)
    env = gym.make(env_id, xml_file=str(path))
    rng = np.random.default_rng(0)
    ends = []
    for e in range(episodes):
        env.reset(seed=e)
        done = False
        while not done:
            _, _, terminated, truncated, info = env.step(rng.uniform(-1.0, 1.0, 6))
            done = terminated or truncated
        ends.append(info["x_position"])
    env.close()
    return np.array(ends)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--episodes", type=int, default=20)
    p.add_argument("--write-stiff", metavar="PATH",
                   help="write the stiff-contacts variant to PATH (for learning_parity.py --xml) and stop")
    args = p.parse_args()
    if args.write_stiff:
        pathlib.Path(args.write_stiff).write_text(variants()["stiff contacts"])
        return
    for name, xml in variants().items():
        x = drift("HalfCheetah-v5", xml, args.episodes)
        print(f"MuJoCo    {name:<17} x at the end {x.mean():6.2f} ± {x.std():5.2f} m", flush=True)
    import gymfleet  # noqa: F401  (registers the gymfleet/ ids)

    x = drift("gymfleet/HalfCheetah-v5", variants()["as the file says"], args.episodes)
    print(f"gymfleet  {'as the file says':<17} x at the end {x.mean():6.2f} ± {x.std():5.2f} m")


if __name__ == "__main__":
    main()
