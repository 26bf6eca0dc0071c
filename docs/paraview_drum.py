"""Render a recovered drum field as ParaView shows it: the deformed mesh (displacement
scaled up 5x), coloured by the von Mises stress, the scale clipped at 100 MPa so that the
shell's distribution shows (the peak, 1.15 GPa, sits at the back wall's fold behind the
unbalance, where a spider arm's solid tip ends on the sheet: README, `fields`).

    washdyn run reference --scene elastic --states --out out/elastic
    washdyn fields out/elastic --times 178.3 --out out/elastic/top
    xvfb-run -a pvpython docs/paraview_drum.py out/elastic/top/drum_00000.vtu docs/drum_field.png

(Debian's ParaView renders through X: xvfb-run gives it a display; apt-get install paraview
python3-paraview xvfb xauth.)
"""
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, ResetCamera, SaveScreenshot, Show, WarpByVector,
                             XMLUnstructuredGridReader)

src, png = sys.argv[1], sys.argv[2]
grid = XMLUnstructuredGridReader(FileName=[src])
warp = WarpByVector(Input=grid)
warp.Vectors = ["POINTS", "displacement_m"]
warp.ScaleFactor = 5.0
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1200, 900]
if hasattr(view, "UseColorPaletteForBackground"):
    view.UseColorPaletteForBackground = 0
view.Background = [1.0, 1.0, 1.0]
view.OrientationAxesVisibility = 1
shown = Show(warp, view)
ColorBy(shown, ("POINTS", "von_mises_Pa"))
lut = GetColorTransferFunction("von_mises_Pa")
lut.ApplyPreset("Viridis (matplotlib)", True)
lut.RescaleTransferFunction(0.0, 1.0e8)
lut.AutomaticRescaleRangeMode = "Never"
shown.SetScalarBarVisibility(view, True)
bar = GetScalarBar(lut, view)
bar.Title = "von Mises [Pa], clipped at 1e8 (mesh warped 5x)"
bar.ComponentTitle = ""
bar.TitleColor = [0, 0, 0]
bar.LabelColor = [0, 0, 0]
view.CameraPosition = [1.6, -1.2, 1.1]
view.CameraFocalPoint = [-0.05, 0.0, 0.45]
view.CameraViewUp = [0.0, 0.0, 1.0]
ResetCamera(view)
SaveScreenshot(png, view, ImageResolution=[1200, 900])
