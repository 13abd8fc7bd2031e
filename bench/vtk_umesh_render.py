#!/usr/bin/python3
"""Render a .vtu with VTK's vtkUnstructuredGridVolumeRayCastMapper the way `volstream render` does.

Same camera (position, focal point, view up, vertical view angle), same image size and background,
the same colour map samples (viridis, the 33 control points volstream uses, interpolated in sRGB)
over the same --range, and the same opacity: volstream's ALPHA is an opacity per --unit-distance,
which VTK's unstructured-grid integrators read as an attenuation coefficient (opacity value /
unit distance, then exp(-tau * length)), so the script gives VTK tau = -ln(1 - ALPHA) per unit
distance, sampled densely enough that the piecewise-linear ALPHA ramps stay the same.

--compositing linear (default) matches volstream's blending: the colour map goes to VTK in linear
RGB, VTK renders over a transparent black background, the RGBA frame is read back and composited
over the background and encoded to sRGB here (as volstream does). --compositing srgb is plain VTK
use: sRGB colours, composited as they are, VTK's own background.

Prints one JSON line with the times (seconds, wall clock, time.perf_counter):
  read        vtkXMLUnstructuredGridReader.Update()
  tetrahedralize  vtkDataSetTriangleFilter (only when the mesh holds non-tetrahedra: the Bunyk
              ray cast function handles tetrahedra only), else 0
  render[i]   renderWindow.Render() i = 0, 1, ...: the first includes VTK's own set-up (face
              connectivity of the Bunyk ray caster, the pre-integration table), later ones are
              the steady state
  import      `import vtk`; output: reading the frame back, compositing, writing the PNG
and writes the image to -o (PNG, RGB 8-bit).

Run under an X server, e.g. `xvfb-run -a /usr/bin/python3 bench/vtk_umesh_render.py ...`.
"""
import argparse
import json
import math
import os
import struct
import sys
import time
import zlib

# volstream's viridis (src/volstream/render/optics/color_maps.cpp): entries 0, 8, ..., 248 and 255
# of matplotlib's 256-entry table, sRGB-encoded, evenly spaced over [0, 1].
VIRIDIS = [
    (0.267004, 0.004874, 0.329415), (0.277018, 0.050344, 0.375715), (0.282327, 0.094955, 0.417331),
    (0.282884, 0.135920, 0.453427), (0.278826, 0.175490, 0.483397), (0.270595, 0.214069, 0.507052),
    (0.258965, 0.251537, 0.524736), (0.244972, 0.287675, 0.537260), (0.229739, 0.322361, 0.545706),
    (0.214298, 0.355619, 0.551184), (0.199430, 0.387607, 0.554642), (0.185556, 0.418570, 0.556753),
    (0.172719, 0.448791, 0.557885), (0.160665, 0.478540, 0.558115), (0.149039, 0.508051, 0.557250),
    (0.137770, 0.537492, 0.554906), (0.127568, 0.566949, 0.550556), (0.120565, 0.596422, 0.543611),
    (0.120638, 0.625828, 0.533488), (0.132268, 0.655014, 0.519661), (0.157851, 0.683765, 0.501686),
    (0.196571, 0.711827, 0.479221), (0.246070, 0.738910, 0.452024), (0.304148, 0.764704, 0.419943),
    (0.369214, 0.788888, 0.382914), (0.440137, 0.811138, 0.340967), (0.515992, 0.831158, 0.294279),
    (0.595839, 0.848717, 0.243329), (0.678489, 0.863742, 0.189503), (0.762373, 0.876424, 0.137064),
    (0.845561, 0.887322, 0.099702), (0.926106, 0.897330, 0.104071), (0.993248, 0.906157, 0.143936),
]


def srgb_to_linear(c):
    c = min(max(c, 0.0), 1.0)
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def linear_to_srgb(c):
    c = min(max(c, 0.0), 1.0)
    return c * 12.92 if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055


def interp(points, x):
    """Piecewise-linear interpolation of sorted (x, value) pairs, clamped at both ends."""
    if x <= points[0][0]:
        return points[0][1]
    if x >= points[-1][0]:
        return points[-1][1]
    for (x0, v0), (x1, v1) in zip(points, points[1:]):
        if x <= x1:
            t = (x - x0) / (x1 - x0) if x1 > x0 else 1.0
            return v0 + (v1 - v0) * t
    return points[-1][1]


def triple(text, name):
    v = [float(s) for s in text.split(",")]
    if len(v) != 3:
        sys.exit(f"{name}: want X,Y,Z, got {text!r}")
    return v


def write_png(path, width, height, rgb_rows):
    """RGB 8-bit PNG; rgb_rows: top row first, each a bytes object of 3 * width."""
    raw = b"".join(b"\x00" + row for row in rgb_rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("vtu")
    ap.add_argument("-o", "--output", required=True, help="output PNG")
    ap.add_argument("--field", default="density", help="point array to render")
    ap.add_argument("--range", required=True, help="LO,HI of the colour map (as volstream's --range)")
    ap.add_argument("--opacity", required=True, help="VALUE:ALPHA,... as volstream's --opacity (ALPHA per unit distance)")
    ap.add_argument("--unit-distance", type=float, required=True, help="world length over which ALPHA applies")
    ap.add_argument("--camera-pos", required=True)
    ap.add_argument("--camera-at", required=True)
    ap.add_argument("--camera-up", default="0,1,0")
    ap.add_argument("--fov", type=float, default=35.0, help="vertical view angle, degrees")
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--background", default="0.06,0.06,0.08", help="R,G,B in [0,1], sRGB (volstream's default)")
    ap.add_argument("--renders", type=int, default=2, help="number of timed renders (>= 1)")
    ap.add_argument("--integrator", choices=["auto", "preintegration", "partial", "linear", "homogeneous"], default="auto",
                    help="VTK ray integrator (auto: the mapper's choice for point scalars, pre-integration)")
    ap.add_argument("--compositing", choices=["linear", "srgb"], default="linear")
    ap.add_argument("--tf-samples", type=int, default=256,
                    help="control points for the colour and opacity functions over the range")
    ap.add_argument("--threads", type=int, default=0, help="mapper threads (0: VTK's default, all cores)")
    ap.add_argument("--tetrahedralize", choices=["auto", "always", "never"], default="auto")
    args = ap.parse_args()

    t_start = time.perf_counter()
    import vtk  # noqa: E402 (after argparse so --help works without VTK)
    t_import = time.perf_counter() - t_start

    width, height = (int(s) for s in args.size.lower().split("x"))
    lo, hi = (float(s) for s in args.range.split(","))
    bg = triple(args.background, "--background")
    opacity_pts = []
    for item in args.opacity.split(","):
        v, a = item.split(":")
        opacity_pts.append(((float(v) - lo) / (hi - lo), float(a)))  # volstream: positions normalised over the range
    opacity_pts.sort()
    linear = args.compositing == "linear"
    times = {"vtk": vtk.vtkVersion.GetVTKVersion(), "compositing": args.compositing, "import": t_import}

    t0 = time.perf_counter()
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.vtu)
    reader.Update()
    times["read"] = time.perf_counter() - t0
    grid = reader.GetOutput()
    if grid.GetPointData().GetArray(args.field) is None:
        sys.exit(f"{args.vtu}: no point array {args.field!r}")
    times["cells"] = grid.GetNumberOfCells()
    times["points"] = grid.GetNumberOfPoints()

    types = vtk.vtkCellTypes()
    grid.GetCellTypes(types)
    only_tets = all(types.GetCellType(i) == vtk.VTK_TETRA for i in range(types.GetNumberOfTypes()))
    times["tetrahedralize"] = 0.0
    data = grid
    if args.tetrahedralize == "always" or (args.tetrahedralize == "auto" and not only_tets):
        t0 = time.perf_counter()
        tf = vtk.vtkDataSetTriangleFilter()
        tf.SetInputData(grid)
        tf.TetrahedraOnlyOn()
        tf.Update()
        data = tf.GetOutput()
        times["tetrahedralize"] = time.perf_counter() - t0
        times["tets"] = data.GetNumberOfCells()

    # Transfer functions, sampled over [lo, hi] like volstream's baked table (colours interpolated in
    # sRGB, then linearised on baking), clamped outside the range (VTK's default clamping).
    ctf = vtk.vtkColorTransferFunction()
    ctf.SetColorSpaceToRGB()
    otf = vtk.vtkPiecewiseFunction()
    cmap = [[(i / 32.0, VIRIDIS[i][c]) for i in range(33)] for c in range(3)]
    xs = sorted(set([i / args.tf_samples for i in range(args.tf_samples + 1)] + [p[0] for p in opacity_pts if 0 <= p[0] <= 1]))
    for x in xs:
        value = lo + x * (hi - lo)
        rgb = [interp(cmap[c], x) for c in range(3)]
        if linear:
            rgb = [srgb_to_linear(c) for c in rgb]
        ctf.AddRGBPoint(value, *rgb)
        alpha = min(max(interp(opacity_pts, x), 0.0), 1.0)
        tau = -math.log(1.0 - alpha) if alpha < 1.0 else 50.0  # attenuation per unit distance
        otf.AddPoint(value, tau)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(ctf)
    prop.SetScalarOpacity(otf)
    prop.SetScalarOpacityUnitDistance(args.unit_distance)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()

    mapper = vtk.vtkUnstructuredGridVolumeRayCastMapper()
    mapper.SetInputData(data)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectScalarArray(args.field)
    mapper.AutoAdjustSampleDistancesOff()  # else later renders may drop resolution to meet a frame rate
    mapper.SetImageSampleDistance(1.0)
    if args.threads > 0:
        mapper.SetNumberOfThreads(args.threads)
    integrators = {"preintegration": vtk.vtkUnstructuredGridPreIntegration,
                   "partial": vtk.vtkUnstructuredGridPartialPreIntegration,
                   "linear": vtk.vtkUnstructuredGridLinearRayIntegrator,
                   "homogeneous": vtk.vtkUnstructuredGridHomogeneousRayIntegrator}
    if args.integrator != "auto":
        mapper.SetRayIntegrator(integrators[args.integrator]())
    times["threads"] = mapper.GetNumberOfThreads()

    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    ren = vtk.vtkRenderer()
    ren.AddVolume(volume)
    if linear:
        ren.SetBackground(0.0, 0.0, 0.0)
        ren.SetBackgroundAlpha(0.0)
    else:
        ren.SetBackground(*bg)
    cam = ren.GetActiveCamera()
    cam.SetPosition(*triple(args.camera_pos, "--camera-pos"))
    cam.SetFocalPoint(*triple(args.camera_at, "--camera-at"))
    cam.SetViewUp(*triple(args.camera_up, "--camera-up"))
    cam.SetViewAngle(args.fov)  # vertical (UseHorizontalViewAngle is off)
    ren.ResetCameraClippingRange()

    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetAlphaBitPlanes(1)
    win.SetMultiSamples(0)
    win.SetSize(width, height)
    win.AddRenderer(ren)

    renders = []
    for _ in range(max(1, args.renders)):
        t0 = time.perf_counter()
        win.Render()
        renders.append(time.perf_counter() - t0)
    times["render"] = renders
    times["mapper_time_to_draw"] = mapper.GetTimeToDraw()
    times["integrator"] = mapper.GetRayIntegrator().GetClassName() if mapper.GetRayIntegrator() else \
        ("vtkUnstructuredGridPreIntegration (automatic)")

    # Read the frame back (RGBA, bottom row first) and write the PNG.
    t_out = time.perf_counter()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.SetInputBufferTypeToRGBA()
    grab.ReadFrontBufferOff()
    grab.ShouldRerenderOff()  # read the frame just rendered (the default renders it once more)
    grab.Update()
    img = grab.GetOutput()
    w, h, _ = img.GetDimensions()
    arr = img.GetPointData().GetScalars()
    ncomp = arr.GetNumberOfComponents()
    flat = bytes(memoryview(arr))  # VTK arrays export the buffer protocol
    # The frame: premultiplied colour (linear mode: linear RGB) and alpha in [0, 255].
    try:
        import numpy as np
    except ImportError:
        np = None
    if linear and np is not None:
        px = np.frombuffer(flat, dtype=np.uint8).reshape(h, w, ncomp)[::-1].astype(np.float64) / 255.0
        lin = px[:, :, :3] + (1.0 - px[:, :, 3:4]) * np.array([srgb_to_linear(c) for c in bg])
        lin = np.clip(lin, 0.0, 1.0)
        enc = np.where(lin <= 0.0031308, lin * 12.92, 1.055 * lin ** (1 / 2.4) - 0.055)
        out = np.rint(255.0 * enc).astype(np.uint8)
        rows = [out[y].tobytes() for y in range(h)]
        coverage = float((px[:, :, 3] > 0).mean())
    elif linear:
        bg_lin = [srgb_to_linear(c) for c in bg]
        # 8-bit alpha and colour: out = to_srgb(C + (1 - A) * bg), exact per pixel.
        cache = {}
        rows = []
        for y in range(h - 1, -1, -1):
            row = bytearray(3 * w)
            base = y * w * ncomp
            for x in range(w):
                p = base + x * ncomp
                key = flat[p:p + 4]
                out = cache.get(key)
                if out is None:
                    a = key[3] / 255.0
                    out = bytes(round(255 * linear_to_srgb(key[c] / 255.0 + (1.0 - a) * bg_lin[c])) for c in range(3))
                    cache[key] = out
                row[3 * x:3 * x + 3] = out
            rows.append(bytes(row))
        coverage = sum(1 for i in range(3, len(flat), ncomp) if flat[i] > 0) / float(w * h)
    else:
        rows = []
        for y in range(h - 1, -1, -1):
            base = y * w * ncomp
            row = bytearray(3 * w)
            for x in range(w):
                p = base + x * ncomp
                row[3 * x:3 * x + 3] = flat[p:p + 3]
            rows.append(bytes(row))
        coverage = None
    write_png(args.output, w, h, rows)
    times["output"] = time.perf_counter() - t_out
    times["alpha_coverage"] = coverage
    times["image"] = os.path.abspath(args.output)
    print(json.dumps(times), flush=True)


if __name__ == "__main__":
    main()
