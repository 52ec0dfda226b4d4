# The README's Python example: simulate a tau+ table and plot it against LRPB23 Eq. 22.
# usage: PYTHONPATH=build/python /usr/bin/python3 scripts/python_tau_plus_example.py  (writes tau_plus.png)
import matplotlib; matplotlib.use("Agg"); import matplotlib.pyplot as plt
import numpy as np, mcref
cfg = {"geometry": {"kind": "micrograin", "tau0": 0.5, "beta": 1.0, "tile": 150}, "run": {"batches": 16},
       "measure": [{"quantity": "tau_plus", "theta_i_deg": [0, 20, 40, 60, 70, 80, 85, 89], "samples": 20000}]}
t = mcref.simulate(cfg, seed=1, threads=2)["tau_plus"]
theta, value, err = t.axis("theta_i").centres, t.value[:, 0], t.stderr[:, 0]
model = mcref.micrograin.tau_plus_eq22(0.5, 1.0, theta)            # LRPB23 Eq. 22
for row in zip(np.degrees(theta), value, err, model): print("%5.1f deg  sim %.4f ± %.4f  Eq.22 %.4f" % row)
x = np.linspace(0, np.pi / 2 - 1e-3, 200)
plt.errorbar(np.degrees(theta), value, 2 * err, fmt="o", label="mcref.simulate (±2σ)")
plt.plot(np.degrees(x), mcref.micrograin.tau_plus_eq22(0.5, 1.0, x), label="τ⁺, LRPB23 Eq. 22")
plt.xlabel("θ_i (deg)"); plt.ylabel("τ⁺"); plt.legend(); plt.savefig("tau_plus.png", dpi=80)
