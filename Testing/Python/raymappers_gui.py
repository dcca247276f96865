"""Screenshots of the GUI test, taken from ParaView's Python shell during the XML playback
(Testing/XML/TestRayMappersGUI.xml) and compared afterwards by TestRayMappersGUI.py.

shot(name) saves the active view as $RAYMAPPERS_GUI_OUTPUT/name.png at 300 x 300 the way
ParaView's own pqcompareview captures it: the view's size set to the image's (so no
magnification tiles), the PPI to 72, both restored after."""
import os

import paraview.simple
from paraview.simple import GetActiveView, SaveScreenshot

SIZE = [300, 300]
# paraview.simple resets the camera at the first render it makes of a view; the GUI test's
# views are framed by the playback.
paraview.simple._DisableFirstRenderCameraReset()


def shot(name):
    view = GetActiveView()
    size, ppi = list(view.ViewSize), view.PPI
    view.ViewSize, view.PPI = SIZE, 72
    view.StillRender()
    SaveScreenshot(os.path.join(os.environ['RAYMAPPERS_GUI_OUTPUT'], name + '.png'), view,
                   ImageResolution=SIZE, TransparentBackground=0)
    view.ViewSize, view.PPI = size, ppi
    view.StillRender()
