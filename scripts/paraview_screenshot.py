#!/usr/bin/env pvpython
"""Render an aries XDMF output with ParaView (pvpython), the way a ParaView user would look at it: the rest geometry
warped by the `displacement` field with scale 1 (WarpByVector; docs/options.md: the XDMF geometry is the rest shape),
coloured by a cell field (colour range to its 99th percentile), with ParaView's colour legend.

usage: pvpython scripts/paraview_screenshot.py OUTPUT.xmf PNG [--field von_mises] [--step K] [--size 900x700]
                                                             [--view X,Y,Z]
On a machine without a display: xvfb-run -a pvpython --force-offscreen-rendering scripts/paraview_screenshot.py ...
(Debian: apt-get install paraview python3-paraview xvfb). --step is the output step's index in the file's time
series (default: the last).
"""
import argparse
import sys

from paraview import simple as pv


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("xmf")
    ap.add_argument("png")
    ap.add_argument("--field", default="von_mises")
    ap.add_argument("--step", type=int, default=-1)
    ap.add_argument("--size", default="900x700")
    ap.add_argument("--view", default="1,-1.6,0.9", help="direction from the body to the camera (z is up)")
    ap.add_argument("--check-positions", metavar="OUTPUT_BASE", default=None,
                    help="also compare ParaView's warped points with the positions in the step's .h5 file")
    a = ap.parse_args()
    reader = pv.XDMFReader(registrationName="aries", FileNames=[a.xmf])
    reader.UpdatePipelineInformation()
    tv = reader.TimestepValues
    try:
        times = [float(v) for v in tv]
    except TypeError:  # a single time step is a scalar property
        times = [float(tv)] if tv is not None else [0.0]
    times = times or [0.0]
    t = times[a.step]
    reader.UpdatePipeline(t)
    cells = reader.CellData.keys()
    if a.field not in cells:
        sys.exit("paraview_screenshot: error: cell field '%s' is not in %s (cell fields: %s)"
                 % (a.field, a.xmf, ", ".join(cells)))
    warp = pv.WarpByVector(Input=reader)
    warp.Vectors = ["POINTS", "displacement"]
    warp.ScaleFactor = 1.0
    w, h = (int(v) for v in a.size.split("x"))
    view = pv.CreateView("RenderView")
    view.ViewSize = [w, h]
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    display = pv.Show(warp, view)
    pv.ColorBy(display, ("CELLS", a.field))
    # Stress concentrates in a few cells: the colour range ends at the 99th percentile (as scripts/render_png.py).
    from paraview import servermanager
    from vtk.util.numpy_support import vtk_to_numpy
    import numpy as np
    values = vtk_to_numpy(servermanager.Fetch(reader).GetCellData().GetArray(a.field))
    if values.ndim > 1:
        values = np.linalg.norm(values, axis=1)
    lo, top = float(values.min()), float(np.percentile(values, 99.0))
    lut = pv.GetColorTransferFunction(a.field)
    lut.RescaleTransferFunction(lo, top if top > lo else lo + 1e-30)
    lut.ApplyPreset("Inferno (matplotlib)", True)
    display.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(lut, view)
    bar.Title = "%s (t = %g)" % (a.field, t)
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    ex, ey, ez = (float(v) for v in a.view.split(","))
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraPosition = [ex, ey, ez]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera()
    pv.Render(view)
    pv.SaveScreenshot(a.png, view, ImageResolution=[w, h])
    if a.check_positions:
        import os
        import h5py
        from aries_output import step_files
        steps = step_files(a.check_positions)
        with h5py.File(steps[a.step], "r") as f:
            positions = f["/positions"][:]
        warped = vtk_to_numpy(servermanager.Fetch(warp).GetPoints().GetData())
        print("warped geometry vs positions: max |diff| %.3e (%s)" % (np.abs(warped - positions).max(),
                                                                     os.path.basename(steps[a.step])))
    print("wrote %s: %s at t = %g, range %.4g .. %.4g (colours to the 99th percentile %.4g), %d time steps"
          % (a.png, a.field, t, lo, float(values.max()), top, len(times)))


if __name__ == "__main__":
    main()
