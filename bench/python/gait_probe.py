"""Open-loop sine gaits on gymfleet and MuJoCo (issue L3's HalfCheetah finding): N gaits
(random amplitude, frequency and phases per actuator), 300 steps each, on
`gymfleet/<Name>-v5` (one batch) and Gymnasium's `<Name>-v5`; prints the forward reward on
both sides and their correlation across gaits. Each side's reset draws its own initial
noise (gymfleet's generator is not Gymnasium's), so the gaits also start apart; the last
line repeats the gaits with MuJoCo put in gymfleet's initial state (`set_state` from
`env.unwrapped.data`), the comparison on the same state. Not a test.

    python bench/python/gait_probe.py HalfCheetah 64     # needs gymfleet, gymnasium, mujoco
    python bench/python/gait_probe.py Hopper 64          # any v5 id: its actuators and step
"""
import sys, numpy as np, gymnasium as gym
import gymfleet  # noqa: F401  (registers the gymfleet/ ids)
name = sys.argv[1] if len(sys.argv) > 1 else "HalfCheetah"
N = int(sys.argv[2]) if len(sys.argv) > 2 else 64
T = 300
rng = np.random.default_rng(0)
probe = gym.make(f"{name}-v5")
na = probe.action_space.shape[0]  # the model's actuators
dt = probe.unwrapped.dt  # its control step (timestep × frame skip)
probe.close()
amp = rng.uniform(0.3, 1.0, (N, na)); freq = rng.uniform(0.5, 4.0, (N, 1)); ph = rng.uniform(0, 2*np.pi, (N, na))
def act(k, dt):
    return np.clip(amp * np.sin(2*np.pi*freq*k*dt + ph), -1, 1).astype(np.float32)
# gymfleet
venv = gym.make_vec(f"gymfleet/{name}-v5", N)
venv.reset(seed=0)
R = np.zeros(N); F = np.zeros(N); alive = np.ones(N, bool)
for k in range(T):
    o, r, te, tr, info = venv.step(act(k, dt))
    R += r * alive; F += np.asarray(info["reward_forward"]) * alive
    alive &= ~(te | tr)
venv.close()
# mujoco
Rm = np.zeros(N); Fm = np.zeros(N)
for i in range(N):
    e = gym.make(f"{name}-v5"); e.reset(seed=i)
    for k in range(T):
        o, r, te, tr, info = e.step(act(k, dt)[i])
        Rm[i] += r; Fm[i] += info["reward_forward"]
        if te or tr: break
print("gymfleet forward mean %.1f max %.1f | mujoco mean %.1f max %.1f" % (F.mean(), F.max(), Fm.mean(), Fm.max()))
print("corr", np.corrcoef(F, Fm)[0,1])
# The same gaits from the same state: MuJoCo set to each gymfleet env's initial state.
Fs = np.zeros(N); Fms = np.zeros(N)
for i in range(N):
    g = gym.make(f"gymfleet/{name}-v5"); g.reset(seed=i)
    e = gym.make(f"{name}-v5"); e.reset(seed=i)
    e.unwrapped.set_state(np.asarray(g.unwrapped.data.qpos, float), np.asarray(g.unwrapped.data.qvel, float))
    live = [True, True]
    for k in range(T):
        a = act(k, dt)[i]
        for j, (env, out) in enumerate(((g, Fs), (e, Fms))):
            if live[j]:
                o, r, te, tr, info = env.step(a)
                out[i] += info["reward_forward"]
                live[j] = not (te or tr)
    g.close(); e.close()
print("corr from the same initial state %.3f (forward mean gymfleet %.1f, mujoco %.1f)" % (np.corrcoef(Fs, Fms)[0, 1], Fs.mean(), Fms.mean()))
idx = np.argsort(-F)[:8]
for i in idx: print(i, "freq %.2f" % freq[i,0], "gf %.1f mj %.1f" % (F[i], Fm[i]))
idx = np.argsort(-Fm)[:5]
for i in idx: print("mj-best", i, "freq %.2f" % freq[i,0], "gf %.1f mj %.1f" % (F[i], Fm[i]))
