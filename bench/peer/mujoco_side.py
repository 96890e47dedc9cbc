#!/usr/bin/env python3
"""The MuJoCo side of the gymfleet peer benchmark.

Measures what one *env step* costs in plain MuJoCo (single thread, Python bindings)
for the same assemblies gymfleet simulates (bench/peer/models/*.xml, checked
against models/*.json by check_models.py), and what envpool's C++ MuJoCo
Reacher-v5 achieves in batch.

One env step = `substeps` calls of mujoco.mj_step with model.opt.timestep =
dt / substeps, so every env step advances dt of simulated time (dt = 1/240 s by
default, as in gymfleet). Integrator: Euler (MuJoCo's semi-implicit Euler, with
implicit joint damping). Reset (mj_resetData) every 1000 env steps, like our
benchmark; the reset is inside the timed loop.

Variants (data.ctrl is a joint torque in N*m: <motor gear="1">):
  zero       ctrl = 0 from the exact qpos0. Our models start upright, an exact
             unstable equilibrium that MuJoCo (f64, exactly symmetric) never leaves,
             so nothing moves: the cheapest case, and the one gymfleet's B3 bench uses.
  zero+tilt  ctrl = 0, qpos0 + U(-0.01, 0.01) rad per joint after every reset, so the
             arms fall and swing like they do in an f32 simulator whose round-off tips
             them over.
  sine       tau_j = A_j sin(2*pi*f_j*t + phi_j), f_j in [0.5, 1.5] Hz
  random     tau_j ~ U(-A_j, A_j), held for one env step (like a policy at 1/dt Hz)
  A_j = min(m_sub,j * g * l_j + 10 rad/s^2 * M_jj,  100 rad/s^2 / (M^-1)_jj)
  (see torque_amplitudes): a motor that can roughly hold its arm out horizontally,
  capped so that no joint alone is driven harder than 100 rad/s^2. Joints then hit
  their limits and links touch each other sometimes (contacts are on).
In every variant ctrl is written each env step from a precomputed table, so the
variants differ only in physics, not in Python overhead.

Python overhead: the "plain" loop makes `substeps` binding calls per env step
(about 0.3-1 us each); mj_step(m, d, nstep=substeps) makes one. The plain loop
is the honest equivalent of gymfleet's per-substep stepping; nstep shows how
much of it is the binding.

Reacher-v5 (envpool 1.2.5 and gymnasium 1.4, same reacher.xml):
  <option timestep="0.01" integrator="RK4"/> and frame_skip = 2
  (envpool.make_spec("Reacher-v5").config.frame_skip == 2; gymnasium
  reacher_v5.py: frame_skip: int = 2), so one env step = 2 RK4 steps of 0.01 s
  = 0.02 s simulated (RK4 costs ~4 model evaluations per step). Episodes are 50
  steps (max_episode_steps=50), after which envpool auto-resets. 2 actuated DOF
  (+2 slide joints for the target); every geom has contype=0, so no contacts.
  verify_reacher_dt() reproduces an envpool step bit-for-bit with
  mujoco.mj_step(nstep=2) on that xml, which confirms these numbers.

Usage:
  /tmp/peer/bin/python bench/peer/mujoco_side.py --substeps 5
  /tmp/peer/bin/python bench/peer/mujoco_side.py --substeps 16 --models arm6 chain20 --no-envpool
"""
import argparse
import math
import os
import statistics
import sys
import time

import numpy as np
import mujoco

HERE = os.path.dirname(os.path.abspath(__file__))
MODELS = ["pendulum", "arm2", "arm6", "chain20"]
RESET_EVERY = 1000
G = 9.81

REACHER_TIMESTEP = 0.01      # reacher.xml <option timestep>
REACHER_FRAME_SKIP = 2       # envpool/gymnasium default for Reacher-v5
REACHER_DT = REACHER_TIMESTEP * REACHER_FRAME_SKIP  # 0.02 s per env step


def model_path(name):
    return os.path.join(HERE, "models", name + ".xml")


def reacher_xml_path():
    import envpool_assets  # noqa: F401  (ships the exact xml envpool loads)
    base = os.path.dirname(envpool_assets.__file__) if getattr(envpool_assets, "__file__", None) \
        else list(envpool_assets.__path__)[0]
    return os.path.join(base, "mujoco", "assets_gym", "reacher.xml")


def torque_amplitudes(m, alpha=10.0, alpha_cap=100.0):
    """Per-actuator ctrl amplitude A_j (N*m for gear 1), from the model at qpos0:

        A_j = min(m_sub,j * g * l_j + alpha * M_jj,  alpha_cap / (M^-1)_jj)

    first term: hold the mass moved by joint j out horizontally (l_j = distance of its
    COM from the axis) plus a modest acceleration; cap: at most alpha_cap rad/s^2 of
    joint acceleration when all other joints are free. Without the cap, independent
    random holding torques on a long chain put huge net torques on single light links
    (chain20 then blew up within 6 env steps even with RK4).
    """
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    try:  # MuJoCo >= 3.4/4.0: mj_fullM(m, d, dst); d.qM is gone (now d.M)
        mujoco.mj_fullM(m, d, M)
    except TypeError:  # older: mj_fullM(m, dst, qM)
        mujoco.mj_fullM(m, M, d.qM)
    Minv_diag = np.diag(np.linalg.inv(M)) if m.nv else np.zeros(0)
    amp = np.zeros(m.nu)
    for a in range(m.nu):
        j = m.actuator_trnid[a][0]
        dof = m.jnt_dofadr[j]
        b = m.jnt_bodyid[j]
        r = d.subtree_com[b] - d.xanchor[j]
        ax = d.xaxis[j]
        lever = np.linalg.norm(r - ax * (r @ ax))
        tau = m.body_subtreemass[b] * G * lever + M[dof, dof] * alpha
        tau = min(tau, alpha_cap / Minv_diag[dof])
        ctrl = tau / m.actuator_gear[a][0]
        if m.actuator_ctrllimited[a]:
            ctrl = min(ctrl, m.actuator_ctrlrange[a][1])
        amp[a] = ctrl
    return amp


def ctrl_table(m, n, dt, torque, seed=0):
    """(n, nu) table of ctrl values, one row per env step."""
    if torque == "zero" or m.nu == 0:
        return np.zeros((n, m.nu))
    amp = torque_amplitudes(m)
    rng = np.random.default_rng(seed)
    if torque == "random":
        return rng.uniform(-1.0, 1.0, (n, m.nu)) * amp
    if torque == "ctrlrange":  # uniform over each actuator's ctrlrange (what envpool's random actions do)
        lo, hi = m.actuator_ctrlrange[:, 0], m.actuator_ctrlrange[:, 1]
        return lo + (hi - lo) * rng.uniform(0.0, 1.0, (n, m.nu))
    if torque == "sine":
        f = rng.uniform(0.5, 1.5, m.nu)
        phi = rng.uniform(0.0, 2 * math.pi, m.nu)
        t = (np.arange(n) % RESET_EVERY)[:, None] * dt
        return amp * np.sin(2 * math.pi * f * t + phi)
    raise ValueError("torque must be zero, sine, random or ctrlrange")


def qpos_table(m, n_resets, init_tilt, seed=1):
    """Initial qpos per reset: qpos0, plus U(-init_tilt, init_tilt) rad on every hinge."""
    q = np.tile(m.qpos0, (n_resets, 1))
    if init_tilt:
        q += np.random.default_rng(seed).uniform(-init_tilt, init_tilt, q.shape)
    return q


def _load(xml_path, dt, substeps, integrator):
    m = mujoco.MjModel.from_xml_path(xml_path)
    m.opt.timestep = dt / substeps
    if integrator is not None:
        m.opt.integrator = getattr(mujoco.mjtIntegrator, "mjINT_" + integrator.upper())
    return m, mujoco.MjData(m)


def _run_plain(m, d, table, q0, substeps, reset_every):
    step = mujoco.mj_step
    reset = mujoco.mj_resetData
    ctrl = d.ctrl
    qpos = d.qpos
    t0 = time.perf_counter()
    for i in range(table.shape[0]):
        if i % reset_every == 0:
            reset(m, d)
            qpos[:] = q0[i // reset_every]
        ctrl[:] = table[i]
        for _ in range(substeps):
            step(m, d)
    return time.perf_counter() - t0


def _run_nstep(m, d, table, q0, substeps, reset_every):
    step = mujoco.mj_step
    reset = mujoco.mj_resetData
    ctrl = d.ctrl
    qpos = d.qpos
    t0 = time.perf_counter()
    for i in range(table.shape[0]):
        if i % reset_every == 0:
            reset(m, d)
            qpos[:] = q0[i // reset_every]
        ctrl[:] = table[i]
        step(m, d, substeps)
    return time.perf_counter() - t0


def mujoco_us_per_env_step(xml_path, dt=1 / 240, substeps=4, steps=4000, repeats=5,
                           torque="zero", nstep=False, integrator="Euler", init_tilt=0.0,
                           reset_every=RESET_EVERY, seed=0, return_stats=False):
    """Median wall-clock microseconds per env step (= `substeps` mj_step calls of dt/substeps).

    torque: "zero", "sine", "random" (see the module docstring) or "ctrlrange" (uniform
           over each actuator's ctrlrange; for models that have one, e.g. Reacher).
    nstep: False -> a Python loop of `substeps` mj_step calls (the honest equivalent);
           True  -> one mj_step(m, d, nstep=substeps) call per env step.
    integrator: "Euler" (default), "RK4", "implicit", "implicitfast", or None to keep the xml's.
    init_tilt: after each reset, add U(-init_tilt, init_tilt) rad to every joint (0: exact qpos0).
           Upright models are exact unstable equilibria: in MuJoCo (f64, exactly symmetric)
           they never leave them with zero torque, whereas an f32 simulator's round-off
           tips them over; a small tilt reproduces the falling, swinging motion.
    return_stats: also return a dict with all repeats, mean contacts / active joint
           limits per env step and the number of MuJoCo instability resets (BADQACC).
    """
    m, d = _load(xml_path, dt, substeps, integrator)
    table = ctrl_table(m, steps, dt, torque, seed)
    q0 = qpos_table(m, steps // reset_every + 1, init_tilt)
    run = _run_nstep if nstep else _run_plain
    run(m, d, table[: min(steps, 200)], q0, substeps, reset_every)  # warm-up
    times = [run(m, d, table, q0, substeps, reset_every) for _ in range(repeats)]
    us = [t / steps * 1e6 for t in times]
    med = statistics.median(us)
    if not return_stats:
        return med
    # separate, untimed pass along the same trajectory: contacts, limits, blow-ups
    bad_w = mujoco.mjtWarning.mjWARN_BADQACC
    lim_t = mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT
    ncon = nlim = nbad = 0
    vmax = 0.0
    for i in range(steps):
        if i % reset_every == 0:
            nbad += d.warning[bad_w].number  # mj_resetData clears the counters
            mujoco.mj_resetData(m, d)
            d.qpos[:] = q0[i // reset_every]
        d.ctrl[:] = table[i]
        mujoco.mj_step(m, d, substeps)
        ncon += d.ncon
        nlim += int(np.sum(d.efc_type[: d.nefc] == lim_t))
        vmax = max(vmax, float(np.abs(d.qvel).max()) if m.nv else 0.0)
    nbad += d.warning[bad_w].number
    return med, dict(repeats_us=us, mean_contacts=ncon / steps, mean_limits=nlim / steps,
                     blowups=nbad, max_qvel=vmax, nv=m.nv, timestep=m.opt.timestep)


def verify_reacher_dt(seed=3):
    """Check that one envpool Reacher-v5 step == mj_step(nstep=2) at timestep 0.01 (RK4)."""
    import envpool
    spec = envpool.make_spec("Reacher-v5")
    env = envpool.make("Reacher-v5", env_type="gymnasium", num_envs=1, batch_size=1,
                       num_threads=1, seed=seed)
    obs, _ = env.reset()
    o = obs[0]
    a = np.array([0.7, -0.4])
    o2 = env.step(a[None])[0][0]
    m = mujoco.MjModel.from_xml_path(reacher_xml_path())
    d = mujoco.MjData(m)
    d.qpos[:2] = np.arctan2(o[2:4], o[0:2])
    d.qpos[2:] = o[4:6]
    d.qvel[:2] = o[6:8]
    d.ctrl[:] = a
    mujoco.mj_step(m, d, REACHER_FRAME_SKIP)
    pred = np.concatenate([np.cos(d.qpos[:2]), np.sin(d.qpos[:2]), d.qpos[2:], d.qvel[:2]])
    err = float(np.abs(pred - o2[:8]).max())
    return dict(frame_skip=spec.config.frame_skip, timestep=m.opt.timestep,
                integrator=mujoco.mjtIntegrator(m.opt.integrator).name,
                dt=m.opt.timestep * spec.config.frame_skip,
                max_episode_steps=spec.config.max_episode_steps, replay_max_abs_err=err)


def envpool_reacher_steps_per_s(num_envs=64, num_threads=2, seconds=5.0, seed=0):
    """Env steps per second (all envs together) of envpool Reacher-v5, sync mode, random actions.

    One env step = frame_skip 2 x RK4 timestep 0.01 s = 0.02 s simulated.
    """
    return envpool_steps_per_s("Reacher-v5", num_envs, num_threads, seconds, seed)


def envpool_steps_per_s(task, num_envs=64, num_threads=2, seconds=5.0, seed=0):
    """Env steps per second (all envs together) of an envpool task, sync mode, uniform random
    actions in [-1, 1] (the MuJoCo tasks' ctrl range)."""
    import envpool
    env = envpool.make(task, env_type="gymnasium", num_envs=num_envs,
                       batch_size=num_envs, num_threads=num_threads, seed=seed)
    env.reset()
    rng = np.random.default_rng(seed)
    acts = rng.uniform(-1.0, 1.0, (256, num_envs) + env.action_space.shape)
    for i in range(50):  # warm-up
        env.step(acts[i % 256])
    n = 0
    t0 = time.perf_counter()
    deadline = t0 + seconds
    while True:
        for _ in range(32):
            env.step(acts[n % 256])
            n += 1
        now = time.perf_counter()
        if now >= deadline:
            break
    return n * num_envs / (now - t0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--substeps", type=int, default=4)
    ap.add_argument("--dt", type=float, default=1 / 240)
    ap.add_argument("--steps", type=int, default=4000, help="env steps per repeat")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--models", nargs="*", default=MODELS)
    ap.add_argument("--tilt", type=float, default=0.01, help="rad, for the zero+tilt variant")
    ap.add_argument("--no-envpool", action="store_true")
    ap.add_argument("--envpool-seconds", type=float, default=5.0)
    ap.add_argument("--envpool-threads", type=int, default=2)
    ap.add_argument("--envpool-envs", type=int, default=64)
    args = ap.parse_args(argv)

    print("mujoco %s, numpy %s, python %s, %d CPUs visible" % (
        mujoco.__version__, np.__version__, sys.version.split()[0], os.cpu_count()))
    print("env step = %d x mj_step at timestep %.6g s = dt %.6g s; Euler; reset every %d env steps; "
          "median of %d repeats x %d env steps" % (args.substeps, args.dt / args.substeps, args.dt,
                                                   RESET_EVERY, args.repeats, args.steps))
    print("us/env-step: plain = Python loop of mj_step (the honest equivalent), nstep = mj_step(nstep=substeps)")
    print("variants: zero = zero torque from the exact upright qpos0; zero+tilt = zero torque from "
          "qpos0 + U(+-%g rad) per joint;" % args.tilt)
    print("          sine / random = torques of amplitude A_j (printed below), from qpos0")
    print("%-9s %3s %-10s %9s %9s %11s %9s %9s %8s %9s" % (
        "model", "nv", "variant", "plain", "nstep", "us/mj_step", "contacts", "limits", "blowups",
        "max|qvel|"))
    kw = dict(dt=args.dt, substeps=args.substeps, steps=args.steps, repeats=args.repeats)
    variants = [("zero", "zero", 0.0), ("zero+tilt", "zero", args.tilt), ("sine", "sine", 0.0),
                ("random", "random", 0.0)]
    amps = {}
    for name in args.models:
        p = model_path(name)
        amps[name] = torque_amplitudes(mujoco.MjModel.from_xml_path(p))
        for label, tq, tilt in variants:
            plain, st = mujoco_us_per_env_step(p, torque=tq, init_tilt=tilt, return_stats=True, **kw)
            ns = mujoco_us_per_env_step(p, torque=tq, init_tilt=tilt, nstep=True, **kw)
            print("%-9s %3d %-10s %9.2f %9.2f %11.3f %9.2f %9.2f %8d %9.1f" % (
                name, st["nv"], label, plain, ns, plain / args.substeps, st["mean_contacts"],
                st["mean_limits"], st["blowups"], st["max_qvel"]))
            sys.stdout.flush()
    print("contacts / limits: mean active contacts / joint-limit constraints per env step (after it);"
          " blowups: MuJoCo BADQACC auto-resets; max|qvel| in rad/s")
    print("torque amplitudes A_j (N*m), joint order:")
    for name, a in amps.items():
        print("  %-9s %s" % (name, " ".join("%.3g" % x for x in a)))

    if not args.no_envpool:
        rx = reacher_xml_path()
        print("\nReacher-v5 reference (xml %s)" % rx)
        v = verify_reacher_dt()
        print("  frame_skip %d x timestep %g s (%s) = dt %g s per env step, max_episode_steps %d; "
              "envpool step replayed with mj_step(nstep=2): max |err| = %.3g" % (
                  v["frame_skip"], v["timestep"], v["integrator"], v["dt"], v["max_episode_steps"],
                  v["replay_max_abs_err"]))
        one = mujoco_us_per_env_step(rx, dt=REACHER_DT, substeps=REACHER_FRAME_SKIP, steps=args.steps,
                                     repeats=args.repeats, torque="ctrlrange", integrator=None,
                                     reset_every=50)
        print("  plain-Python MuJoCo, 1 thread, random ctrl in [-1,1], reset every 50: %.2f us/env-step "
              "(%.0f env-steps/s)" % (one, 1e6 / one))
        sps = envpool_reacher_steps_per_s(num_envs=args.envpool_envs, num_threads=args.envpool_threads,
                                          seconds=args.envpool_seconds)
        print("  envpool Reacher-v5, %d envs, batch %d, %d threads, sync, random actions: "
              "%.0f env-steps/s (%.2f us/env-step/thread, %.0f simulated s per wall s)" % (
                  args.envpool_envs, args.envpool_envs, args.envpool_threads, sps,
                  1e6 * args.envpool_threads / sps, sps * REACHER_DT))
    return 0


if __name__ == "__main__":
    sys.exit(main())
