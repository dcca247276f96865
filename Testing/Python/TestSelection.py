"""pvpython: ParaView's hardware selection on Ray-Traced Spheres, against an analytic answer.

The scene is two lattices of N x M points (a Plane source each), one at z = 0 and one right
behind it at z = -3, drawn as spheres of radius R (less than half the spacing: gaps between
them) and seen head-on through a parallel projection. Every back sphere is then exactly
behind a front one, and where each sphere lands in the view follows from the camera alone:
display = centre of the view + (world - focal point) * pixels per unit. Checks, each against
the points expected from their coordinates here (no code shared with the mapper), the
selection compared as the set of the extracted points' coordinates:
- Select Points On over the whole view: exactly the front lattice's points;
- a rectangle whose edges run through the gaps: exactly the points inside it;
- a polygon (a triangle): every sphere wholly inside it, none wholly outside;
- the selected spheres, and only they, show the selection colour (SelectionColor, also
  when changed);
- one-pixel selections (what Hover Points and Interactive Select ask) at three sphere
  centres: exactly that sphere's point;
- Find Data's query selection (id < N: the first row) is highlighted the same way;
- Select Cells On: the Plane's cells are quads, no vertex cells, so no sphere has a cell to
  select: nothing (the mapper's rule for cell selection);
- a volume in front of the spheres: ParaView's own Volume of an unstructured grid selects
  nothing and hides the spheres from the selection (its projected tetrahedra draw colours in
  every selection pass); an SPH Volume there does the same (vtkRayMapperCore::
  PresentSelectionFootprint), and hides nothing when moved aside or behind the spheres
  (with several ranks, the spheres then exchanged between them: the rectangle's selection
  and highlight are still exact).
With --server PVSERVER [--ranks N --launcher ENV] the same checks run in a client-server
session (on N MPI ranks the lattices are redistributed among the ranks first, each rank
draws its part, and the selection must name each point's process and its id there).

usage: pvpython TestSelection.py PLUGIN [--server PVSERVER [--ranks N --launcher ENV]]
"""
import os
import subprocess
import sys

from paraview.simple import (  # noqa: E402
    AppendGeometry, ClearSelection, Connect, CreateView, Delete, Disconnect, ExtractSelection,
    LoadPlugin, Plane, RedistributeDataSet, Render, SelectSurfaceCells, SelectSurfacePoints,
    SetActiveSource, Show, Hide, Tetrahedralize, Transform, Wavelet, GetDisplayProperties,
    QuerySelect)
from paraview import servermanager  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish, prepare_view, screenshot  # noqa: E402

N, M = 12, 8          # the lattice: N columns (x), M rows (y), spacing 1
BACK = -3.0           # the hidden lattice's z
R = 0.3               # sphere radius: gaps of 1 - 2R between neighbours
SIZE = [400, 300]
SCALE = 5.0           # ParallelScale: half the view's height in world units
PIXELS = SIZE[1] / (2 * SCALE)  # pixels per world unit
CENTER = ((N - 1) / 2.0, (M - 1) / 2.0)
RANKS = 1             # the server's ranks (main sets it)
OUTPUT = '.'          # where screenshots go (main sets it)


def display(x, y):
    """The display position of world (x, y) (pixel (i, j) spans [i, i + 1))."""
    return (SIZE[0] / 2.0 + (x - CENTER[0]) * PIXELS, SIZE[1] / 2.0 + (y - CENTER[1]) * PIXELS)


def make_scene(view, split):
    planes = []
    for z in (0.0, BACK):
        planes.append(Plane(Origin=[0, 0, z], Point1=[N - 1, 0, z], Point2=[0, M - 1, z],
                            XResolution=N - 1, YResolution=M - 1))
    source = AppendGeometry(Input=planes)
    if split:
        # Both lattices split among the server's ranks, so each rank draws and selects its
        # own part, and the selection must name the right process.
        planes.append(source)
        source = RedistributeDataSet(Input=source)
    rep = Show(source, view)
    rep.SetRepresentationType('Ray-Traced Spheres')
    rep.Radius = R
    # paraview.simple resets the camera at a view's first render: render once before.
    Render(view)
    view.CameraParallelProjection = 1
    view.CameraPosition = [CENTER[0], CENTER[1], 10]
    view.CameraFocalPoint = [CENTER[0], CENTER[1], 0]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelScale = SCALE
    view.OrientationAxesVisibility = 0
    Render(view)
    coords = []
    for plane in planes[:2]:
        data = servermanager.Fetch(plane)
        coords += [tuple(round(c, 6) for c in data.GetPoint(i))
                   for i in range(data.GetNumberOfPoints())]
    return source, rep, planes, coords


def selected_points(source, processes=None):
    """The points of the source's selection, as a set of coordinate triples (the extracted
    selection fetched to the client); `processes`, when given, receives the processes the
    selection names (its IDSelectionSources' (process, id) pairs)."""
    selection = source.GetSelectionInput(0)
    if selection is None:
        return set()
    if processes is not None:
        # ParaView 5.11 wraps the selection in AppendSelections (one input per selection).
        inputs = selection.Input if selection.GetXMLName() == 'AppendSelections' else [selection]
        for s in inputs:
            processes |= set(list(s.IDs)[0::2])
    extract = ExtractSelection(Input=source, Selection=selection)
    points = set()
    # Each rank's piece on its own (Fetch's gather of all ranks returned only the first
    # rank's unstructured grid here).
    for rank in range(RANKS):
        data = servermanager.Fetch(extract, rank)
        for i in range(data.GetNumberOfPoints()):
            points.add(tuple(round(c, 6) for c in data.GetPoint(i)))
    Delete(extract)
    return points


def front(coords, inside=lambda x, y: True):
    return {c for c in coords if c[2] == 0.0 and inside(c[0], c[1])}


def check_rectangle(source, coords, view, where):
    # Columns 2..6 and rows 1..4: the edges lie half way between spheres.
    x0, y0 = display(2 - 0.5, 1 - 0.5)
    x1, y1 = display(6 + 0.5, 4 + 0.5)
    SelectSurfacePoints(Rectangle=[int(x0), int(y0), int(x1), int(y1)], View=view)
    expected = front(coords, lambda x, y: 2 <= x <= 6 and 1 <= y <= 4)
    got = selected_points(source)
    check(got == expected, '%s: a rectangle through the gaps selects its %d spheres (got %d, '
          '%d missing, %d extra)' % (where, len(expected), len(got), len(expected - got),
                                     len(got - expected)))
    check_highlight(view, coords, expected, [1.0, 0.0, 1.0], where)
    # ParaView's palette sets every representation's SelectionColor.
    source_rep = GetDisplayProperties(source, view)
    source_rep.SelectionColor = [0.0, 1.0, 0.0]
    check_highlight(view, coords, expected, [0.0, 1.0, 0.0], where)
    source_rep.SelectionColor = [1.0, 0.0, 1.0]


def check_highlight(view, coords, selected, color, where):
    """The selected spheres show the selection colour, the others do not: the pixel at each
    front sphere's centre (lit head-on: the colour times the diffuse and ambient light) has
    the colour's hue exactly when the sphere is selected."""
    image = screenshot(view, os.path.join(OUTPUT, 'selection.png'), SIZE).reshape(
        SIZE[1], SIZE[0], 3)
    wrong = []
    for p in front(coords):
        x, y = display(p[0], p[1])
        r, g, b = image[int(y), int(x)]
        tinted = (r > g + 60 and b > g + 60) if color == [1.0, 0.0, 1.0] else (
            g > r + 60 and g > b + 60)
        if tinted != (p in selected):
            wrong.append(p)
    check(not wrong, '%s: the %d selected spheres, and only they, show the selection colour '
          '%s (%d wrong)' % (where, len(selected), color, len(wrong)))


def segment_distance(p, a, b):
    ax, ay = a
    bx, by = b
    px, py = p
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
    return ((px - ax - t * dx) ** 2 + (py - ay - t * dy) ** 2) ** 0.5


def inside_polygon(p, polygon):
    x, y = p
    inside = False
    for k in range(len(polygon)):
        (ax, ay), (bx, by) = polygon[k], polygon[(k + 1) % len(polygon)]
        if (ay > y) != (by > y) and x < ax + (y - ay) * (bx - ax) / (by - ay):
            inside = not inside
    return inside


def check_polygon(source, coords, view, where):
    triangle = [display(0.2, 0.1), display(9.7, 1.4), display(3.1, 6.6)]
    triangle = [(int(x), int(y)) for x, y in triangle]
    SelectSurfacePoints(Polygon=[c for p in triangle for c in p], View=view)
    got = selected_points(source)
    radius = R * PIXELS
    wholly_in, wholly_out = set(), set()
    for p in front(coords):
        c = display(p[0], p[1])
        edge = min(segment_distance(c, triangle[k], triangle[(k + 1) % 3]) for k in range(3))
        if inside_polygon(c, triangle) and edge > radius + 1.5:
            wholly_in.add(p)
        elif not inside_polygon(c, triangle) and edge > radius + 1.5:
            wholly_out.add(p)
    check(wholly_in and wholly_in <= got and not (got & wholly_out) and
          got <= front(coords),
          '%s: a polygon selects the %d spheres wholly inside it and none of the %d wholly '
          'outside (got %d)' % (where, len(wholly_in), len(wholly_out), len(got)))


def check_picks(source, coords, view, where):
    for p in sorted(front(coords))[5::29][:3]:
        x, y = display(p[0], p[1])
        SelectSurfacePoints(Rectangle=[int(x), int(y), int(x), int(y)], View=view)
        got = selected_points(source)
        check(got == {p}, '%s: one pixel at the centre of the sphere at %s selects it (got %s)'
              % (where, p, sorted(got)))


def run_checks(where, ranks):
    view = CreateView('RenderView')
    prepare_view(view, SIZE, [0.1, 0.1, 0.15])
    # In client-server, the server renders (and so selects) however small the data.
    view.RemoteRenderThreshold = 0.0
    source, rep, planes, coords = make_scene(view, ranks > 1)
    SetActiveSource(source)
    check(len(coords) == 2 * N * M, '%s: %d points' % (where, len(coords)))

    SelectSurfacePoints(Rectangle=[0, 0, SIZE[0] - 1, SIZE[1] - 1], View=view)
    expected = front(coords)
    processes = set()
    got = selected_points(source, processes)
    check(processes == set(range(ranks)), '%s: the selection names the processes that hold '
          'the points (%s)' % (where, sorted(processes)))
    check(got == expected, '%s: Select Points On over the whole view selects the %d front '
          'spheres and none behind them (got %d, %d missing, %d extra)'
          % (where, len(expected), len(got), len(expected - got), len(got - expected)))
    check_rectangle(source, coords, view, where)
    check_polygon(source, coords, view, where)
    check_picks(source, coords, view, where)

    # Find Data: a query selection (the first lattice row, ids below N in the builtin
    # session's order; on several ranks the ids are each rank's own) is highlighted too.
    ClearSelection(source)
    if ranks == 1:
        QuerySelect(QueryString='id < %d' % N, FieldType='POINT', Source=source)
        row = front(coords, lambda x, y: y == 0.0)
        got = selected_points(source)
        check(got == row, '%s: Find Data (id < %d) selects the first row (got %d)'
              % (where, N, len(got)))
        check_highlight(view, coords, row, [1.0, 0.0, 1.0], where + ', Find Data')

    ClearSelection(source)
    SelectSurfaceCells(Rectangle=[0, 0, SIZE[0] - 1, SIZE[1] - 1], View=view)
    got = selected_points(source)
    check(not got, '%s: Select Cells On spheres without vertex cells selects nothing (got %d)'
          % (where, len(got)))

    # A volume in front of the spheres: ParaView's own Volume of an unstructured grid
    # (projected tetrahedra) selects nothing and hides them from the selection; an SPH
    # Volume there must do the same, and nothing once it is moved aside.
    ClearSelection(source)
    wavelet = Wavelet(WholeExtent=[0, 4, 0, 4, 0, 1])
    grid = Tetrahedralize(Input=wavelet)
    grid_volume = Transform(Input=grid)
    grid_volume.Transform.Scale = [N / 2.0, M / 2.0, 0.5]
    grid_volume.Transform.Translate = [-1.5, -1.5, 1.5]
    volume_source = Plane(Origin=[-1, -1, 2], Point1=[N, -1, 2], Point2=[-1, M, 2],
                          XResolution=30, YResolution=30)
    for case, volume_of, representation in (('ParaView\'s Volume', grid_volume, 'Volume'),
                                            ('an SPH Volume', volume_source, 'SPH Volume')):
        volume = Show(volume_of, view)
        volume.SetRepresentationType(representation)
        Render(view)
        SetActiveSource(source)
        SelectSurfacePoints(Rectangle=[0, 0, SIZE[0] - 1, SIZE[1] - 1], View=view)
        got, got_volume = selected_points(source), selected_points(volume_of)
        check(not got and not got_volume, '%s: %s in front hides the spheres from the '
              'selection and selects nothing itself (got %d spheres, %d volume points)'
              % (where, case, len(got), len(got_volume)))
        Hide(volume_of, view)
        ClearSelection(source)
    volume = Show(volume_source, view)
    volume.Position = [3 * N, 0, 0]
    Render(view)
    SelectSurfacePoints(Rectangle=[0, 0, SIZE[0] - 1, SIZE[1] - 1], View=view)
    got = selected_points(source)
    check(got == expected, '%s: the SPH Volume moved aside hides nothing (got %d spheres)'
          % (where, len(got)))
    # With a volume in the view and several ranks, each rank draws (and selects) the spheres
    # reaching into its box of the volume's partition, its own and the other ranks': moved
    # aside, the boxes leave all spheres to one rank; behind the spheres, a box face cuts
    # through the lattice and its spheres. Either way the selection and its highlight name
    # the spheres as the ranks that hold them do.
    check_rectangle(source, coords, view, where + ', the SPH Volume aside')
    volume.Position = [0, 0, -7]
    Render(view)
    ClearSelection(source)
    SelectSurfacePoints(Rectangle=[0, 0, SIZE[0] - 1, SIZE[1] - 1], View=view)
    got = selected_points(source)
    check(got == expected, '%s: the SPH Volume behind the spheres hides nothing (got %d '
          'spheres, %d missing, %d extra)' % (where, len(got), len(expected - got),
                                              len(got - expected)))
    check_rectangle(source, coords, view, where + ', the SPH Volume behind')
    planes += [grid_volume, grid, wavelet]
    ClearSelection(source)
    for proxy in [volume_source, source] + planes:
        Delete(proxy)
    Delete(view)


def main():
    plugin = sys.argv[1]
    options = dict(zip(sys.argv[2::2], sys.argv[3::2]))
    global RANKS, OUTPUT
    OUTPUT = options.get('--output', '.')
    os.makedirs(OUTPUT, exist_ok=True)
    LoadPlugin(plugin, remote=False, ns=globals())
    if '--server' not in options:
        run_checks('builtin', 1)
        return finish()
    from TestClientServer import start_server
    ranks = int(options.get('--ranks', 1))
    RANKS = ranks
    out_dir = OUTPUT
    process, port, copier = start_server(
        options['--server'], os.path.join(out_dir, 'pvserver-selection-%d.log' % ranks), ranks,
        options.get('--launcher'))
    try:
        check(port is not None, 'pvserver listens (port %s)' % port)
        if port is not None:
            Connect('localhost', port)
            LoadPlugin(plugin, remote=True, ns=globals())
            run_checks('%d server rank%s' % (ranks, 's' if ranks > 1 else ''), ranks)
            Disconnect()
            Connect()
    finally:
        if process.poll() is None:
            try:
                process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        copier.join()
    return finish()


if __name__ == '__main__':
    code = main()
    if code:
        sys.exit(code)
