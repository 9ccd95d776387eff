"""The sliding case's convergence study (paper 000, section 4.2) from Python: the same numbers as
`moreau study examples/sliding.toml` for the same methods and step sizes.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/sliding_convergence.py [OUT_DIR]

Writes OUT_DIR/convergence.png (default out/python_sliding): error against h per method.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import moreau  # noqa: E402

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python_sliding")
out.mkdir(parents=True, exist_ok=True)

case = moreau.pbd.SlidingCase(dimension=3, C=10.0, alpha=np.pi / 16, T=4.0)
methods = ["pbd", "pngs", "pgs", "penalty:1000"]
hs = [0.4 / 2**k for k in range(10)]
table = moreau.pbd.study(case, methods, hs, abstol=1e-12, reltol=1e-10, max_sweeps=100000)

fig, ax = plt.subplots(figsize=(6, 4.5))
for method in methods:
    rows = [i for i, m in enumerate(table["method"]) if m == method]
    h, error = table["h"][rows], table["error"][rows]
    order = moreau.pbd.observed_order(list(h[-4:]), list(error[-4:]))
    ax.loglog(h, error, "o-", label=f"{method} (order {order:.2f})")
ax.set_xlabel("h")
ax.set_ylabel("max error against the exact solution")
ax.legend()
ax.set_title("sliding case")
fig.tight_layout()
fig.savefig(out / "convergence.png", dpi=120)
print(f"wrote {out / 'convergence.png'}")
