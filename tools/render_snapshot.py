# Renders one spall snapshot (a snap_NNNNNN.xmf or the series.xmf of a run) to a PNG with
# ParaView: particles as points coloured by one field. Run it through tools/render_snapshot,
# which supplies pvpython, offscreen rendering and a virtual display when there is none.
import argparse
import os
import sys

from paraview.simple import (Clip, GetColorTransferFunction, GetScalarBar, LoadPalette, Render,
                             SaveScreenshot, CreateView, Show, ColorBy, Text, XDMFReader,
                             ExtractSurface, Transform, RotationalExtrusion)


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
    p.add_argument("--point-size", type=float, default=3.0,
                   help="point size in pixels in 1D and 2D (3D draws spheres)")
    p.add_argument("--clip", choices=["x", "y", "z", "none"], default="y",
                   help="3D only: cut away the half of the particles on the camera's side of the "
                        "plane through the centre normal to this axis, so that the inside shows "
                        "(default y; 'none' shows the outside of the cloud)")
    p.add_argument("--revolve", type=float, metavar="DEGREES",
                   help="an rz run: sweep its (r, z) points about the axis through this angle "
                        "(e.g. 270 for a cut-away view, 360 for the whole body) and draw the "
                        "3D body")
    p.add_argument("--segments", type=int, default=48,
                   help="with --revolve: copies of each particle around the sweep (default 48)")
    p.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"),
                   help="colour range (default: the data range of the snapshot shown)")
    p.add_argument("--out", required=True, help="PNG file to write")
    return p.parse_args()


def usage_error(message):
    print("render_snapshot: " + message, file=sys.stderr)
    sys.exit(2)


def main():
    a = parse_args()
    try:
        width, height = (int(v) for v in a.size.lower().split("x"))
    except ValueError:
        usage_error("--size must be WxH, e.g. 1200x800, not '%s'" % a.size)
    if not os.path.isfile(a.xmf):
        usage_error("no such file: %s" % a.xmf)
    # The XDMF reader of ParaView's (Xdmf3ReaderS reads the files too: tests/cli/test_snapshot_readers.py).
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
        usage_error("no field '%s' in %s (has: %s)" % (a.field, a.xmf, ", ".join(sorted(fields))))
    ncomp = reader.PointData[a.field].GetNumberOfComponents()

    # Flat data (1D, 2D) is seen face on from +z; 3D from an oblique corner at (+x, -y, +z),
    # through a cut: a cloud of points otherwise only shows its outside.
    b = reader.GetDataInformation().GetBounds()
    flat = b[5] - b[4] <= 0.0
    data = reader
    if a.revolve is not None:
        if not flat or not 0 < a.revolve <= 360 or a.segments < 2:
            usage_error("--revolve takes an rz snapshot's (r, z) points, an angle in (0, 360] "
                        "and --segments >= 2")
        # rz's axis is y (x = r); ParaView sweeps about z: turn y into z, then sweep. Each
        # particle becomes a ring of segments + 1 points carrying its fields.
        surface = ExtractSurface(Input=reader)
        turned = Transform(Input=surface)
        turned.Transform.Rotate = [90.0, 0.0, 0.0]
        data = RotationalExtrusion(Input=turned)
        data.Resolution = a.segments
        data.Angle = a.revolve
        data.Capping = 0
        data.UpdatePipeline(t)
        b = data.GetDataInformation().GetBounds()
        flat = False
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    source = data
    if not flat and a.clip != "none" and a.revolve is None:
        axis = "xyz".index(a.clip)
        towards_camera = [1.0, -1.0, 1.0][axis]
        normal = [towards_camera if k == axis else 0.0 for k in range(3)]
        # A hair towards the camera, so that a layer of particles on the centre plane stays.
        shift = 1e-6 * (b[2 * axis + 1] - b[2 * axis])
        source = Clip(Input=data)
        source.ClipType = "Plane"
        source.ClipType.Origin = [c + shift * n for c, n in zip(centre, normal)]
        source.ClipType.Normal = normal
        source.Invert = 1  # keep the far side of the plane
        source.UpdatePipeline(t)

    LoadPalette("WhiteBackground")
    view = CreateView("RenderView")
    view.ViewSize = [width, height]
    view.ViewTime = t
    view.OrientationAxesVisibility = 1
    disp = Show(source, view)
    if flat:
        disp.SetRepresentationType("Points")
        disp.PointSize = a.point_size
    else:
        # Points of a few pixels leave the far particles showing through the near ones, so
        # the cut face is unreadable: draw spheres of half the mean spacing instead.
        n = max(data.GetDataInformation().GetNumberOfPoints(), 1)
        volume = max((b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]), 0.0)
        disp.SetRepresentationType("Point Gaussian")
        disp.ShaderPreset = "Sphere"
        disp.GaussianRadius = 0.5 * (volume / n) ** (1.0 / 3.0)
    if ncomp == 1:
        ColorBy(disp, ("POINTS", a.field))
    else:
        ColorBy(disp, ("POINTS", a.field, a.component))
    if a.range:
        GetColorTransferFunction(a.field).RescaleTransferFunction(a.range[0], a.range[1])
    else:
        disp.RescaleTransferFunctionToDataRange(False, True)
    disp.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(GetColorTransferFunction(a.field), view)
    bar.Title = a.field
    bar.ComponentTitle = "" if ncomp == 1 else "(%s)" % a.component

    label = Show(Text(Text="t = %.6g s" % t), view)
    label.WindowLocation = "Upper Left Corner"
    label.FontSize = 14

    view.CameraFocalPoint = centre
    if flat:
        view.InteractionMode = "2D"
        view.CameraPosition = [centre[0], centre[1], centre[2] + 1.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
    else:
        # Mostly face on to the cut (if any), a little from the (+x, -y, +z) corner.
        direction = [1.0, -1.0, 0.8]
        if a.clip != "none" and a.revolve is None:
            axis = "xyz".index(a.clip)
            direction = [d if k == axis else 0.4 * d for k, d in enumerate(direction)]
        view.CameraPosition = [c + d for c, d in zip(centre, direction)]
        view.CameraViewUp = [0.0, 1.0, 0.0] if a.clip == "z" else [0.0, 0.0, 1.0]
    view.ResetCamera(False)
    Render(view)
    SaveScreenshot(a.out, view, ImageResolution=[width, height])


main()
