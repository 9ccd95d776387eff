"""Fill a gap hidden in a real recording (../shared/data/mocap/Vicon.c3d relative to the
repository root) with three methods and compare them with the hidden truth.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/gap_fill.py [OUT_DIR]

Writes OUT_DIR/gap_fill.png (default out/python_gap_fill): one coordinate of the marker around
the gap, truth and fills.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from moreau import mocap  # noqa: E402

root = pathlib.Path(__file__).resolve().parents[2]
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python_gap_fill")
out.mkdir(parents=True, exist_ok=True)

recording, warnings = mocap.read_recording(root.parent / "shared/data/mocap/Vicon.c3d")
truth = np.array(recording.positions)  # a copy we may edit (the view is read-only)
complete = np.flatnonzero(np.isfinite(truth).all(axis=(0, 2)))
marker = int(complete[0])
first, length = recording.frames // 2, int(0.5 * recording.rate)  # half a second hidden
holed = truth.copy()
holed[first:first + length, marker, :] = np.nan
rec = mocap.Recording(recording.labels, holed, recording.rate, recording.units)

frames = np.arange(first - length, first + 2 * length)
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(frames, truth[frames, marker, 0], "k-", lw=3, alpha=0.3, label="truth")
for method in ("spline", "rigid", "pca"):
    filled, summary = mocap.fill_gaps(rec, method=method)
    x = filled.positions[first:first + length, marker]
    error = np.linalg.norm(x - truth[first:first + length, marker], axis=1)
    print(f"{method:7s} {summary.message}: mean error {error.mean():.2f} {recording.units}")
    ax.plot(frames, filled.positions[frames, marker, 0], label=f"{method} ({error.mean():.1f})")
ax.axvspan(first, first + length - 1, color="grey", alpha=0.15)
ax.set_xlabel("frame")
ax.set_ylabel(f"{recording.labels[marker]} x ({recording.units})")
ax.legend()
fig.tight_layout()
fig.savefig(out / "gap_fill.png", dpi=120)
print(f"wrote {out / 'gap_fill.png'}")
