"""Screenshots of the GUI test, taken from ParaView's Python shell during the XML playback
(Testing/XML/TestRayMappersGUI.xml) and compared afterwards by TestRayMappersGUI.py.

shot(name) saves the active view as $RAYMAPPERS_GUI_OUTPUT/name.png at 300 x 300 the way
ParaView's own pqcompareview captures it: the view's size set to the image's (so no
magnification tiles), the PPI to 72, both restored after. selection_report(name) saves
the shot and, as name.json, the point ids the active source's selection names.

translucent_shot(name) takes the shot of the active Ray-Traced Spheres representation without
FXAA and renders its reference (Testing/References, 'render translucent', through
raymappers_reference) as name-reference.png: the spheres of its constant radius, coloured by
its color map, their opacity its opacity array through its opacity function times Opacity."""
import json
import os

import paraview.simple
from paraview.simple import GetActiveView, SaveScreenshot

SIZE = [300, 300]
# paraview.simple resets the camera at the first render it makes of a view; the GUI test's
# views are framed by the playback.
paraview.simple._DisableFirstRenderCameraReset()


def translucent_shot(name):
    import raymappers_reference
    from paraview.simple import GetActiveSource, GetDisplayProperties
    view, rep, source = GetActiveView(), GetDisplayProperties(), GetActiveSource()
    assert rep.UseRadiusArray == 0, 'the reference spheres have the constant radius'
    fxaa = view.UseFXAA
    view.UseFXAA = 0
    shot(name)
    size, ppi = list(view.ViewSize), view.PPI
    view.ViewSize, view.PPI = SIZE, 72
    view.StillRender()
    function = rep.SpheresOpacityTransferFunction.GetClientSideObject()
    radius, opacity, array = rep.Radius * rep.RadiusScale, rep.Opacity, rep.SpheresOpacityArray[1]
    lines = raymappers_reference.camera_lines(view, SIZE) + raymappers_reference.light_lines(view)
    lines += [raymappers_reference.material_line(rep), 'render translucent']
    lines += raymappers_reference.sphere_lines(
        source, rep.ColorArrayName[1], rep.LookupTable.GetClientSideObject(),
        lambda block: [radius] * block.GetNumberOfPoints(),
        lambda block: [opacity * function.GetValue(float(v))
                       for v in raymappers_reference.point_values(block, array)])
    stem = os.path.join(os.environ['RAYMAPPERS_GUI_OUTPUT'], name + '-reference')
    expected = raymappers_reference.render(lines, SIZE, stem)
    raymappers_reference.write_over(expected, view.GetRenderer().GetBackground(), SIZE,
                                    stem + '.png')
    view.ViewSize, view.PPI, view.UseFXAA = size, ppi, fxaa
    view.StillRender()


def shot(name):
    view = GetActiveView()
    size, ppi = list(view.ViewSize), view.PPI
    view.ViewSize, view.PPI = SIZE, 72
    view.StillRender()
    SaveScreenshot(os.path.join(os.environ['RAYMAPPERS_GUI_OUTPUT'], name + '.png'), view,
                   ImageResolution=SIZE, TransparentBackground=0)
    view.ViewSize, view.PPI = size, ppi
    view.StillRender()


def selection_report(name):
    from paraview.simple import GetActiveSource
    selection = GetActiveSource().GetSelectionInput(0)
    ids = []
    if selection is not None:
        # ParaView 5.11 wraps a selection in AppendSelections, (process, id) pairs inside.
        inputs = selection.Input if selection.GetXMLName() == 'AppendSelections' else [selection]
        for s in inputs:
            ids += list(s.IDs)[1::2]
    with open(os.path.join(os.environ['RAYMAPPERS_GUI_OUTPUT'], name + '.json'), 'w') as f:
        json.dump({'selected_points': sorted(set(ids))}, f)
    shot(name)
