"""vtk_peer.py: times VTK's vtkFixedPointVolumeRayCastMapper (CPU ray
caster) on CThead for `pp5 bench --peers`.  Run under Xvfb by run_peers.sh
with Debian's python3-vtk9; not part of the pp5 build.

usage: vtk_peer.py RAW_U16BE NX NY NZ IMAGE_SIDE FRAMES THREADS [PNG] [--mip LO,HI]
--mip: maximum intensity projection (SetBlendModeToMaximumIntensity) with a
grey ramp from LO to HI and opacity 1, as pp5's --blend mip --window;
otherwise shaded compositing with pp5's ct-skin-ramp.
Prints "vtk_ms_per_frame <median>"."""
import sys
import time

import vtk


def set_mip(mapper, prop, lo, hi):
    """MIP over the window lo..hi: grey = material, black below lo."""
    mapper.SetBlendModeToMaximumIntensity()
    opacity = vtk.vtkPiecewiseFunction()
    opacity.AddPoint(0, 1.0)
    opacity.AddPoint(4095, 1.0)
    color = vtk.vtkColorTransferFunction()
    color.AddRGBPoint(min(lo, 0.0), 0.0, 0.0, 0.0)
    color.AddRGBPoint(lo, 0.0, 0.0, 0.0)
    color.AddRGBPoint(hi, 1.0, 1.0, 1.0)
    color.AddRGBPoint(max(hi, 4095.0), 1.0, 1.0, 1.0)
    prop.SetScalarOpacity(opacity)
    prop.SetColor(color)
    prop.ShadeOff()


def main():
    args = sys.argv[1:]
    mip = None
    if "--mip" in args:
        i = args.index("--mip")
        if i + 1 >= len(args):
            print(__doc__)
            return 2
        mip = [float(x) for x in args[i + 1].split(",")]
        del args[i:i + 2]
    if len(args) not in (7, 8):
        print(__doc__)
        return 2
    path = args[0]
    nx, ny, nz, side, frames, threads = (int(a) for a in args[1:7])
    reader = vtk.vtkImageReader2()
    reader.SetFileName(path)
    reader.SetFileDimensionality(3)
    reader.FileLowerLeftOn()                   # keep row order: y as in the file
    reader.SetDataScalarTypeToUnsignedShort()
    reader.SetDataByteOrderToBigEndian()
    reader.SetNumberOfScalarComponents(1)
    reader.SetDataExtent(0, nx - 1, 0, ny - 1, 0, nz - 1)
    reader.SetDataSpacing(1.0, 1.0, 2.0)      # CThead 1:1:2
    reader.Update()

    # pp5's ct-skin-ramp: opacity 0 at 350 rising to 0.8 at 640, 0.8 above.
    opacity = vtk.vtkPiecewiseFunction()
    opacity.AddPoint(0, 0.0)
    opacity.AddPoint(350, 0.0)
    opacity.AddPoint(640, 0.8)
    opacity.AddPoint(4095, 0.8)
    color = vtk.vtkColorTransferFunction()
    color.AddRGBPoint(0, 0.95, 0.75, 0.62)
    color.AddRGBPoint(4095, 0.95, 0.75, 0.62)
    prop = vtk.vtkVolumeProperty()
    prop.SetScalarOpacity(opacity)
    prop.SetColor(color)
    prop.ShadeOn()
    prop.SetAmbient(0.15)
    prop.SetDiffuse(0.85)
    prop.SetSpecular(0.0)
    prop.SetInterpolationTypeToLinear()

    mapper = vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetNumberOfThreads(threads)
    mapper.SetSampleDistance(1.0)
    mapper.SetAutoAdjustSampleDistances(0)
    if mip is not None:
        set_mip(mapper, prop, mip[0], mip[1])
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    ren = vtk.vtkRenderer()
    ren.AddVolume(volume)
    ren.SetBackground(0, 0, 0)
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.AddRenderer(ren)
    win.SetSize(side, side)
    cam = ren.GetActiveCamera()
    cam.ParallelProjectionOn()
    # Face view: look along +y (from the face side) with the vertex up (-z).
    cx, cy, cz = (nx - 1) / 2.0, (ny - 1) / 2.0, (nz - 1)
    cam.SetFocalPoint(cx, cy, cz)
    cam.SetPosition(cx, cy - 1000.0, cz)
    cam.SetViewUp(0, 0, -1)
    ren.ResetCamera()
    # pp5's framing: the largest extent (256 units) spans the image height.
    cam.SetParallelScale(0.5 * max(nx, ny, 2 * nz))
    win.Render()                               # warm-up: builds the mapper's tables
    times = []
    for _ in range(frames):
        cam.Azimuth(1.0)                       # a new view each frame
        t0 = time.perf_counter()
        win.Render()
        times.append((time.perf_counter() - t0) * 1e3)
    times.sort()
    print("vtk_ms_per_frame %.2f" % times[len(times) // 2])
    if len(args) == 8:
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(win)
        grab.Update()
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(args[7])
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()
    return 0


if __name__ == "__main__":
    sys.exit(main())
