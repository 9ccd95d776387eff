"""Renders one frame of a particle trajectory with ParaView: a Glyph of spheres scaled by each
particle's radius, coloured by id (docs/io.md shows the result).

    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
        pvbatch scripts/render_paraview.py OUTPUT_PNG INPUT [TIME]

INPUT is a trajectory.xdmf (opened with the XDMF 3 reader Xdmf3ReaderS) or a VTU series .pvd
(PVDReader). TIME is the simulated time to draw (default: the last frame; the reader's nearest
time step is drawn). 2D trajectories are seen from above, 3D ones from an oblique angle.
pvbatch needs an X display to render on Debian 12, hence xvfb-run; -noreset keeps the virtual
server from resetting between pvbatch's X connections, which otherwise fails now and then
("bad X server connection"). The figure docs/figures/crowd_paraview.png is this script at
TIME = 8 on `moreau run examples/crowd.toml`. Bad usage: a one-line message
on stderr and exit status 2.
"""
import sys

from paraview import simple


def open_trajectory(path):
    if path.endswith(".xdmf"):
        return simple.Xdmf3ReaderS(FileName=[path])
    if path.endswith(".pvd"):
        return simple.PVDReader(FileName=path)
    sys.exit(f"render_paraview.py: {path}: expected a .xdmf or .pvd file")


def draw(reader, time):
    glyph = simple.Glyph(Input=reader, GlyphType="Sphere")
    glyph.OrientationArray = ["POINTS", "No orientation array"]
    glyph.ScaleArray = ["POINTS", "radius"]
    glyph.ScaleFactor = 2.0  # the sphere glyph has diameter 1 at scale 1
    glyph.GlyphMode = "All Points"
    glyph.GlyphType.ThetaResolution = 24
    glyph.GlyphType.PhiResolution = 12
    view = simple.CreateView("RenderView")
    view.ViewSize = [1000, 1000]
    view.ViewTime = time
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    label = simple.Text(Text=f"t = {time:g}")
    label_display = simple.Show(label, view)
    label_display.Color = [0.0, 0.0, 0.0]
    label_display.FontSize = 28
    label_display.WindowLocation = "Upper Left Corner"
    display = simple.Show(glyph, view)
    simple.ColorBy(display, ("POINTS", "id"))
    display.RescaleTransferFunctionToDataRange(True, False)
    simple.GetColorTransferFunction("id").ApplyPreset("Viridis (matplotlib)", True)
    return view


def main():
    if len(sys.argv) not in (3, 4):
        print("usage: render_paraview.py OUTPUT_PNG INPUT [TIME]", file=sys.stderr)
        sys.exit(2)
    output, path = sys.argv[1], sys.argv[2]
    reader = open_trajectory(path)
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues)
    if not times:
        sys.exit(f"render_paraview.py: {path}: no time steps")
    time = float(sys.argv[3]) if len(sys.argv) == 4 else times[-1]
    time = min(times, key=lambda t: abs(t - time))
    reader.UpdatePipeline(time)
    view = draw(reader, time)
    bounds = reader.GetDataInformation().GetBounds()
    view.ResetCamera()
    if bounds[5] - bounds[4] > 0:  # 3D: an oblique view
        view.CameraPosition = [1.0, -1.5, 1.0]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 0.0, 1.0]
        view.ResetCamera()
    else:  # 2D: from above, no perspective
        view.CameraParallelProjection = 1
        view.ResetCamera()
    simple.SaveScreenshot(output, view, ImageResolution=[1000, 1000])
    print(f"render_paraview.py: wrote {output} (t = {time})")


main()
