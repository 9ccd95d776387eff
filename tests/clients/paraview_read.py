"""Opens outputs with ParaView's own readers; run by `pvbatch` (its embedded Python), not pytest.

    pvbatch --force-offscreen-rendering paraview_read.py OUT_DIR READER:FILE [READER:FILE ...]

READER is XDMFReader (XDMF 2), Xdmf3ReaderS, Xdmf3ReaderT, PVDReader or XMLPolyDataReader. For
each job k it writes OUT_DIR/k.npz: `times` (the reader's time steps), and per time step i
`points_i` (N×3), `radius_i`, `id_i`, `cells_i` (the number of cells), `point_NAME_i` for every
point array and `cell_NAME_i` for every cell array, read back through servermanager.Fetch (a file
without time steps, such as geometry.vtp, is read once as step 0). A reader that crashes ParaView
ends the process: the caller sees the exit status and stderr.
"""
import sys

import numpy as np
from paraview import servermanager
from paraview import simple
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkCellCenters


def open_reader(kind, path):
    if kind == "XDMFReader":
        return simple.XDMFReader(FileNames=[path])
    if kind == "PVDReader":
        return simple.PVDReader(FileName=path)
    if kind == "XMLPolyDataReader":
        return simple.XMLPolyDataReader(FileName=[path])
    return getattr(simple, kind)(FileName=[path])


def read_all_steps(kind, path):
    reader = open_reader(kind, path)
    reader.UpdatePipelineInformation()
    times = [float(t) for t in reader.TimestepValues]
    arrays = {"times": np.array(times)}
    for i, t in enumerate(times or [None]):
        if t is None:
            reader.UpdatePipeline()
        else:
            reader.UpdatePipeline(t)
        data = servermanager.Fetch(reader)
        if data.IsA("vtkMultiBlockDataSet"):  # the XDMF 2 reader may wrap a grid in a block
            data = data.GetBlock(0)
        points = data.GetPoints() if data.IsA("vtkPointSet") else None  # image data: implicit
        # Copies: the reader may free its arrays when it moves to the next time step.
        arrays[f"points_{i}"] = (np.array(vtk_to_numpy(points.GetData())) if points is not None
                                 else np.zeros((0, 3)))
        for name in ("radius", "id"):
            array = data.GetPointData().GetArray(name)
            arrays[f"{name}_{i}"] = np.array(vtk_to_numpy(array)) if array is not None else np.zeros(0)
        arrays[f"cells_{i}"] = np.array(data.GetNumberOfCells())
        if data.IsA("vtkImageData"):
            arrays[f"bounds_{i}"] = np.array(data.GetBounds())
            centres = vtkCellCenters()
            centres.SetInputData(data)
            centres.Update()
            arrays[f"cellcentres_{i}"] = np.array(vtk_to_numpy(centres.GetOutput().GetPoints().GetData()))
        for prefix, attributes in (("point", data.GetPointData()), ("cell", data.GetCellData())):
            for a in range(attributes.GetNumberOfArrays()):
                array = attributes.GetArray(a)
                if array is not None:
                    arrays[f"{prefix}_{array.GetName()}_{i}"] = np.array(vtk_to_numpy(array))
    simple.Delete(reader)
    return arrays


def main():
    out_dir, jobs = sys.argv[1], sys.argv[2:]
    for k, job in enumerate(jobs):
        kind, path = job.split(":", 1)
        print(f"paraview_read: {kind} {path}", flush=True)
        np.savez(f"{out_dir}/{k}.npz", **read_all_steps(kind, path))


main()
