# Renders one spall snapshot (a snap_NNNNNN.xmf or the series.xmf of a run) to a PNG with
# ParaView: particles as points coloured by one field. Run it through tools/render_snapshot,
# which supplies pvpython, offscreen rendering and a virtual display when there is none.
import argparse
import sys

from paraview.simple import (GetColorTransferFunction, GetScalarBar, LoadPalette, Render,
                             SaveScreenshot, CreateView, Show, ColorBy, Text, XDMFReader)


def parse_args():
    p = argparse.ArgumentParser(prog="render_snapshot",
                                description="Render a spall snapshot (.xmf) to a PNG.")
    p.add_argument("xmf", help="snap_NNNNNN.xmf or series.xmf")
    p.add_argument("--field", required=True, help="point field to colour by, e.g. pressure")
    when = p.add_mutually_exclusive_group()
    when.add_argument("--time", type=float, help="the snapshot nearest this time (s)")
    when.add_argument("--last", action="store_true", help="the last snapshot (default: first)")
    p.add_argument("--component", default="Magnitude",
                   help="for vector/tensor fields: Magnitude (default) or a component index")
    p.add_argument("--size", default="1200x800", help="image size WxH in pixels")
    p.add_argument("--point-size", type=float, default=3.0)
    p.add_argument("--out", required=True, help="PNG file to write")
    return p.parse_args()


def main():
    a = parse_args()
    width, height = (int(v) for v in a.size.lower().split("x"))
    # The XDMF 2 reader: the Xdmf3 readers cannot read the 1D X_Y_Z geometry spall writes.
    reader = XDMFReader(FileNames=[a.xmf])
    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    if a.last:
        t = times[-1]
    elif a.time is not None:
        t = min(times, key=lambda x: abs(x - a.time))
    else:
        t = times[0]
    reader.UpdatePipeline(t)

    fields = reader.PointData.keys()
    if a.field not in fields:
        sys.exit("render_snapshot: no field '%s' in %s (has: %s)" %
                 (a.field, a.xmf, ", ".join(sorted(fields))))
    ncomp = reader.PointData[a.field].GetNumberOfComponents()

    LoadPalette("WhiteBackground")
    view = CreateView("RenderView")
    view.ViewSize = [width, height]
    view.ViewTime = t
    view.OrientationAxesVisibility = 1
    disp = Show(reader, view)
    disp.SetRepresentationType("Points")
    disp.PointSize = a.point_size
    if ncomp == 1:
        ColorBy(disp, ("POINTS", a.field))
    else:
        ColorBy(disp, ("POINTS", a.field, a.component))
    disp.RescaleTransferFunctionToDataRange(False, True)
    disp.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(GetColorTransferFunction(a.field), view)
    bar.Title = a.field
    bar.ComponentTitle = "" if ncomp == 1 else "(%s)" % a.component

    label = Show(Text(Text="t = %.6g s" % t), view)
    label.WindowLocation = "Upper Left Corner"
    label.FontSize = 14

    # Flat data (1D, 2D) is seen face on from +z; 3D from an oblique corner.
    b = reader.GetDataInformation().GetBounds()
    flat = b[5] - b[4] <= 0.0
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    view.CameraFocalPoint = centre
    if flat:
        view.InteractionMode = "2D"
        view.CameraPosition = [centre[0], centre[1], centre[2] + 1.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
    else:
        view.CameraPosition = [centre[0] + 1.0, centre[1] - 1.0, centre[2] + 0.8]
        view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera(False)
    Render(view)
    SaveScreenshot(a.out, view, ImageResolution=[width, height])


main()
