"""Opens C3D files with ezc3d and with Kinetics Toolkit (`ktk.read_c3d`) and saves what each
reader returns, for test_mocap_clients.py to compare with moreau's own outputs. Runs under the
client suite's virtual environment (the Makefile's CLIENTS_VENV, pinned by requirements.txt), not
under /usr/bin/python3, which has neither package.

    c3d_read.py OUT_DIR FILE.c3d...

writes OUT_DIR/<k>.npz for the k-th file:
  ezc3d_labels, ezc3d_units, ezc3d_rate, ezc3d_first, ezc3d_last (the header's frame range, as
  ezc3d gives it: 0-based), ezc3d_frames (POINT:FRAMES as ezc3d leaves it: the frames it read),
  ezc3d_points (frames × points × 3, NaN where ezc3d reads a sample as missing),
  ezc3d_residuals (frames × points), ezc3d_camera_masks (frames × points × 7),
  ezc3d_trial_range (TRIAL:ACTUAL_START_FIELD and ACTUAL_END_FIELD as frame numbers),
  ezc3d_<TYPE> (the labels of POINT:ANGLES, FORCES, … present), ktk_labels, ktk_time,
  ktk_points (frames × points × 4: x, y, z, 1), ktk_unit;
and prints one line per file. A reader's exception ends the script with its traceback."""
import pathlib
import sys
import warnings

import ezc3d
import numpy as np

POINT_TYPES = ("ANGLES", "FORCES", "MOMENTS", "POWERS", "SCALARS", "REACTIONS")


def labels_of(group, name):
    """A string parameter and its continuations (NAME2, NAME3, …), as one list."""
    values, k = [], 1
    while (key := name if k == 1 else f"{name}{k}") in group:
        values += [str(v) for v in group[key]["value"]]
        k += 1
    return values


def field_frame(value):
    """A TRIAL:ACTUAL_*_FIELD pair of unsigned 16-bit words as one frame number."""
    words = [int(v) & 0xFFFF for v in np.atleast_1d(value)]
    return words[0] + (words[1] << 16 if len(words) > 1 else 0)


def read_ezc3d(path):
    c = ezc3d.c3d(str(path))
    point, header = c["parameters"]["POINT"], c["header"]["points"]
    data = c["data"]
    out = {
        "ezc3d_labels": np.array(labels_of(point, "LABELS"), dtype=str),
        "ezc3d_units": np.array(point["UNITS"]["value"][0]),
        "ezc3d_rate": np.float64(header["frame_rate"]),
        "ezc3d_first": np.int64(header["first_frame"]),
        "ezc3d_last": np.int64(header["last_frame"]),
        "ezc3d_frames": np.int64(np.atleast_1d(point["FRAMES"]["value"])[0]),
        "ezc3d_points": np.transpose(data["points"][:3], (2, 1, 0)),
        "ezc3d_residuals": data["meta_points"]["residuals"][0].T,
        "ezc3d_camera_masks": np.transpose(data["meta_points"]["camera_masks"], (2, 1, 0)),
    }
    trial = c["parameters"].get("TRIAL", {})
    if "ACTUAL_START_FIELD" in trial and "ACTUAL_END_FIELD" in trial:
        out["ezc3d_trial_range"] = np.array([field_frame(trial["ACTUAL_START_FIELD"]["value"]),
                                             field_frame(trial["ACTUAL_END_FIELD"]["value"])])
    for name in POINT_TYPES:
        if name in point:
            out[f"ezc3d_{name}"] = np.array(labels_of(point, name), dtype=str)
    return out


def read_ktk(path):
    import kineticstoolkit as ktk  # imported here: it takes seconds (matplotlib, scikit-learn)

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning of ktk's reader fails the test
        points = ktk.read_c3d(str(path), convert_point_unit=False)["Points"]
    labels = list(points.data)
    return {
        "ktk_labels": np.array(labels, dtype=str),
        "ktk_time": np.asarray(points.time, dtype=np.float64),
        "ktk_points": np.stack([points.data[k] for k in labels], axis=1),
        "ktk_unit": np.array(points.data_info[labels[0]]["Unit"] if labels else ""),
    }


def main(out_dir, paths):
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for k, path in enumerate(paths):
        arrays = read_ezc3d(path) | read_ktk(path)
        np.savez(out_dir / f"{k}.npz", **arrays)
        print(f"{path}: {len(arrays['ezc3d_labels'])} points, "
              f"{arrays['ezc3d_points'].shape[0]} frames")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit("usage: c3d_read.py OUT_DIR FILE.c3d...")
    main(sys.argv[1], sys.argv[2:])
