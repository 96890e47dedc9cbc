#!/usr/bin/env python3
"""Check that bench/peer/models/*.xml (MuJoCo) match models/*.json (gymfleet).

For every non-grounded instance the JSON gives, computed here analytically:
mass, world centre of mass and the inertia tensor about the COM (world axes);
and for every joint: world axis, world anchor, limits and damping. These are
compared with MuJoCo's compiled model after mj_forward at qpos0:

  mass     model.body_mass
  COM      data.xipos
  inertia  ximat @ diag(body_inertia) @ ximat.T  (MuJoCo stores principal moments in
           the inertial frame body_iquat, which may be a permutation of the world
           axes, so the full world tensor is rebuilt and compared element-wise)
  joint    data.xanchor, data.xaxis, model.jnt_range (rad), model.dof_damping,
           parent/child bodies, jnt_limited, gravity
  contact  geom friction, and an <exclude> for every jointed pair

Exits 1 when any quantity differs by more than 1e-6 relative (relative to the norm
of the expected vector/tensor, so exact zeros compare sensibly).

Then a dynamics sanity check on the pendulum: zero torque, timestep 1/1200 s,
0.5 s, joint angle printed every 0.1 s, for several initial tilts, next to a
fine-step RK4 reference of the exact rigid-pendulum ODE.

Usage: /tmp/peer/bin/python bench/peer/check_models.py [model ...]
"""
import json
import math
import os
import sys

import numpy as np
import mujoco

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
MODELS = ["pendulum", "arm2", "arm6", "chain20"]
RTOL = 1e-6
DEFAULT_DENSITY = 1000.0
DEFAULT_FRICTION = 0.5
G = 9.81


def vec3(d, default=(0.0, 0.0, 0.0)):
    if d is None:
        return np.array(default, dtype=float)
    return np.array([d["x"], d["y"], d["z"]], dtype=float)


def solid(prim, position_mm, density):
    """Mass (kg), world COM (m) and inertia about the COM in world axes (kg m^2)
    for an axis-aligned primitive placed at position_mm (no rotation)."""
    p = position_mm / 1000.0
    t = prim["type"]
    if t == "cube":
        a, b, c = (prim["size"][k] / 1000.0 for k in "xyz")
        m = a * b * c * density
        com = p + np.array([a, b, c]) / 2
        I = np.diag([m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12])
    elif t == "cylinder":
        r, h = prim["radius"] / 1000.0, prim["height"] / 1000.0
        m = math.pi * r * r * h * density
        com = p + np.array([0, 0, h / 2])
        ixx = m * (3 * r * r + h * h) / 12
        I = np.diag([ixx, ixx, m * r * r / 2])
    elif t == "sphere":
        r = prim["radius"] / 1000.0
        m = 4.0 / 3.0 * math.pi * r ** 3 * density
        com = p.copy()
        I = np.eye(3) * (2.0 / 5.0 * m * r * r)
    else:
        raise ValueError("unknown primitive " + t)
    return m, com, I


def expected(doc):
    parts = {p["name"]: p for p in doc["parts"]}
    mats = doc.get("materials", {})
    insts = doc["assembly"]["instances"]
    bodies = {}
    for inst in insts:
        if inst.get("rotation") and any(inst["rotation"][k] for k in "xyz"):
            raise SystemExit("rotation not handled by this checker")
        part = parts[inst["part"]]
        mname = inst.get("material") or part.get("material")
        mat = mats.get(mname, {}) if mname else {}
        dens = mat.get("density", DEFAULT_DENSITY)
        fric = mat.get("friction", DEFAULT_FRICTION)
        m, com, I = solid(part["primitive"], vec3(inst.get("position")), dens)
        bodies[inst["name"]] = dict(mass=m, com=com, inertia=I, friction=fric)
    joints = []
    for i, j in enumerate(doc["assembly"].get("joints", [])):
        ax = vec3(j["axis"])
        joints.append(dict(
            name=j.get("name", j["child"]), type=j["type"], parent=j["parent"], child=j["child"],
            anchor=vec3(j.get("anchor")) / 1000.0, axis=ax / np.linalg.norm(ax),
            limited=("min" in j or "max" in j),
            range=np.radians([j.get("min", 0.0), j.get("max", 0.0)]),
            damping=j.get("damping", 0.0)))
    return insts[0]["name"], bodies, joints


class Checker:
    def __init__(self):
        self.rows = []
        self.failures = 0

    def cmp(self, what, got, want):
        got = np.atleast_1d(np.asarray(got, dtype=float))
        want = np.atleast_1d(np.asarray(want, dtype=float))
        scale = max(np.linalg.norm(want), np.linalg.norm(got), 1e-300)
        err = np.linalg.norm(got - want) / scale if (np.linalg.norm(got - want) > 0) else 0.0
        ok = err <= RTOL
        self.failures += (not ok)
        self.rows.append((what, want, got, err, ok))

    def flag(self, what, ok, detail=""):
        self.failures += (not ok)
        self.rows.append((what, detail, "", 0.0 if ok else 1.0, ok))


def fmtv(v):
    if isinstance(v, str):
        return v
    v = np.asarray(v).ravel()
    if v.size == 9:  # show the diagonal of a 3x3, off-diagonals are checked too
        v = v[[0, 4, 8]]
    return "[" + " ".join("%.6g" % x for x in v) + "]"


def check_model(name):
    doc = json.load(open(os.path.join(ROOT, "models", name + ".json")))
    xml = os.path.join(HERE, "models", name + ".xml")
    m = mujoco.MjModel.from_xml_path(xml)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    ground, bodies, joints = expected(doc)
    c = Checker()

    c.cmp("gravity", m.opt.gravity, [0, 0, -G])
    c.flag("integrator Euler", m.opt.integrator == mujoco.mjtIntegrator.mjINT_EULER)
    c.flag("nu == njnt == #joints", m.nu == m.njnt == len(joints), "%d %d %d" % (m.nu, m.njnt, len(joints)))

    for bname, e in bodies.items():
        bid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, bname)
        if bid < 0:
            c.flag(bname + " exists", False)
            continue
        gid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, bname)
        c.cmp(bname + " friction", m.geom_friction[gid][0], e["friction"])
        if bname == ground:
            c.flag(bname + " grounded (no dof, welded to world)",
                   m.body_dofnum[bid] == 0 and m.body_weldid[bid] == 0)
            continue
        c.cmp(bname + " mass", m.body_mass[bid], e["mass"])
        c.cmp(bname + " com", d.xipos[bid], e["com"])
        R = d.ximat[bid].reshape(3, 3)
        Iw = R @ np.diag(m.body_inertia[bid]) @ R.T
        c.cmp(bname + " inertia(world)", Iw, e["inertia"])
        c.cmp(bname + " principal(sorted)", np.sort(m.body_inertia[bid]), np.sort(np.diag(e["inertia"])))

    excl = {frozenset((int(a), int(b))) for a, b in zip(m.exclude_signature >> 16, m.exclude_signature & 0xFFFF)}
    for j in joints:
        jid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, j["name"])
        if jid < 0:
            c.flag(j["name"] + " exists", False)
            continue
        child = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, j["child"])
        parent = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, j["parent"])
        c.flag(j["name"] + " hinge", m.jnt_type[jid] == mujoco.mjtJoint.mjJNT_HINGE and j["type"] == "revolute")
        c.flag(j["name"] + " child/parent", m.jnt_bodyid[jid] == child and m.body_parentid[child] == parent,
               "%s<-%s" % (j["child"], j["parent"]))
        c.cmp(j["name"] + " anchor", d.xanchor[jid], j["anchor"])
        c.cmp(j["name"] + " axis", d.xaxis[jid], j["axis"])
        c.flag(j["name"] + " limited", bool(m.jnt_limited[jid]) == j["limited"], str(j["limited"]))
        if j["limited"]:
            c.cmp(j["name"] + " range(rad)", m.jnt_range[jid], j["range"])
        c.cmp(j["name"] + " damping", m.dof_damping[m.jnt_dofadr[jid]], j["damping"])
        aid = [a for a in range(m.nu) if m.actuator_trnid[a][0] == jid]
        c.flag(j["name"] + " motor gear 1, unlimited",
               len(aid) == 1 and m.actuator_gear[aid[0]][0] == 1.0 and not m.actuator_ctrllimited[aid[0]])
        c.flag(j["name"] + " contact excluded", frozenset((parent, child)) in excl)

    print("== %s  (%s)" % (name, os.path.relpath(xml, ROOT)))
    print("  %-34s %-40s %-40s %9s" % ("quantity", "expected (JSON)", "MuJoCo", "rel.err"))
    for what, want, got, err, ok in c.rows:
        print("  %-34s %-40s %-40s %9.2e %s" % (what, fmtv(want), fmtv(got), err, "ok" if ok else "MISMATCH"))
    return c.failures


def pendulum_ode_reference(theta0, t_end, I_pivot, mgd, h=1e-6):
    """theta'' = mgd sin(theta) / I_pivot, RK4 with a tiny step."""
    y = np.array([theta0, 0.0])
    f = lambda y: np.array([y[1], mgd * math.sin(y[0]) / I_pivot])
    n = int(round(t_end / h))
    for _ in range(n):
        k1 = f(y); k2 = f(y + h / 2 * k1); k3 = f(y + h / 2 * k2); k4 = f(y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return y


def pendulum_dynamics():
    m = mujoco.MjModel.from_xml_path(os.path.join(HERE, "models", "pendulum.xml"))
    d = mujoco.MjData(m)
    dt = 1.0 / 1200.0
    m.opt.timestep = dt
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    # exact pendulum numbers from the JSON: arm 4x4x40 mm, 1000 kg/m^3, pivot at its bottom-face centre
    doc = json.load(open(os.path.join(ROOT, "models", "pendulum.json")))
    _, bodies, joints = expected(doc)
    arm = bodies["arm"]
    r = arm["com"] - joints[0]["anchor"]
    ax = joints[0]["axis"]
    d_perp = np.linalg.norm(r - ax * (r @ ax))
    I_pivot = ax @ arm["inertia"] @ ax + arm["mass"] * d_perp ** 2
    mgd = arm["mass"] * G * d_perp
    print("\n== pendulum dynamics: zero torque, Euler, timestep 1/1200 s, 0.5 s")
    print("   mass %.6g kg, COM %.6g m above the pivot, I_pivot %.6g kg m^2, omega0 = sqrt(mgd/I) = %.6g 1/s"
          % (arm["mass"], d_perp, I_pivot, math.sqrt(mgd / I_pivot)))
    print("   Upright is an exact unstable equilibrium: MuJoCo computes exactly zero gravity torque there,")
    print("   so with theta0 = 0 it never falls. Tilted starts show the fall. Angles in degrees.")
    steps_per_print = int(round(0.1 / dt))
    for theta0_deg in (0.0, 1.0, 10.0):
        mujoco.mj_resetData(m, d)
        d.qpos[0] = math.radians(theta0_deg)
        mujoco.mj_forward(m, d)
        print("   theta0 = %5.1f deg" % theta0_deg)
        print("     %6s %14s %14s %14s %14s" % ("t(s)", "mujoco deg", "ref deg", "mujoco deg/s", "ref deg/s"))
        for k in range(0, 6):
            t = k * 0.1
            ref = pendulum_ode_reference(math.radians(theta0_deg), t, I_pivot, mgd, h=1e-5) if k else \
                np.array([math.radians(theta0_deg), 0.0])
            print("     %6.2f %14.6f %14.6f %14.6f %14.6f" % (
                t, math.degrees(d.qpos[0]), math.degrees(ref[0]), math.degrees(d.qvel[0]), math.degrees(ref[1])))
            if k < 5:
                mujoco.mj_step(m, d, nstep=steps_per_print)
        print("     contacts at end: %d" % d.ncon)


def main(argv):
    names = argv[1:] or MODELS
    print("mujoco", mujoco.__version__)
    failures = 0
    for n in names:
        failures += check_model(n)
    if "pendulum" in names:
        pendulum_dynamics()
    print("\n%s: %d mismatch(es)" % ("FAIL" if failures else "PASS", failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
