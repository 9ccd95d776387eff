"""The figure of scripts/crowd_jupedsim.py (docs/crowds.md, "Side by side with JuPedSim"): the
specific flow against the door width per code (seeds as dots, the mean over the runs that
flowed as a line), the passages of the door line against time (seed 1) and the corridor's mean
speeds."""
import numpy as np


def plot(rows, passages, figure):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx, cx) = plt.subplots(1, 3, figsize=(13, 4))
    style = {"moreau": ("o-", "C0", "-"), "moreau_wall": ("v-.", "C1", "-."),
             "jupedsim": ("s--", "C3", "--"), "jupedsim_steered": ("^:", "C2", ":")}
    for k, (code, (marker, colour, line)) in enumerate(style.items()):
        mine = [r for r in rows if r["scenario"] == "bottleneck" and r["code"] == code]
        widths = sorted({r["parameter"] for r in mine})
        ax.plot([r["parameter"] for r in mine], [r["flow_per_s"] / r["parameter"] for r in mine],
                ".", color=colour, alpha=0.5)
        ax.plot(widths, [np.nanmean([r["flow_per_s"] / b for r in mine if r["parameter"] == b])
                         for b in widths], marker, color=colour, label=f"{code} (seeds: dots)")
        for b, t in passages.items():
            bx.step(t[code], np.arange(1, len(t[code]) + 1), where="post", color=colour,
                    ls=line, lw=1, label=f"{code}, b = {b:g} m")
        mine = [r for r in rows if r["scenario"] == "corridor" and r["code"] == code]
        k = ("moreau", "jupedsim", "jupedsim_steered").index(code) if mine else 0
        for rho in sorted({r["parameter"] for r in mine}):
            v = [r["mean_speed_m_s"] for r in mine if r["parameter"] == rho]
            cx.bar(rho + (k - 1) * 0.25, np.mean(v), width=0.23, color=colour,
                   label=code if rho == mine[0]["parameter"] else None)
            cx.plot([rho + (k - 1) * 0.25] * len(v), v, "k.", ms=3)
    ax.set_xlabel("door width b (m)")
    ax.set_ylabel("specific flow J/b (persons/(m·s))")
    ax.set_ylim(0, 3)
    ax.set_title("Bottleneck: the same people, the same parameters", fontsize=9)
    ax.legend(fontsize=8)
    bx.set_xlabel("time (s)")
    bx.set_ylabel("persons through the door")
    bx.set_title("Passages of the door line (PedPy's N(t)), seed 1", fontsize=9)
    bx.legend(fontsize=7)
    cx.set_xticks(sorted({r["parameter"] for r in rows if r["scenario"] == "corridor"}))
    cx.set_xlabel("initial density in the corridor block (persons/m²)")
    cx.set_ylabel("mean speed in the measurement area (m/s)")
    cx.set_title("Corridor 3 m wide (PedPy, 15–30 s)", fontsize=9)
    cx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(figure, dpi=120)
