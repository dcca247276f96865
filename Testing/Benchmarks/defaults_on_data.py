"""pvpython: every particle representation at its defaults, only ColorBy set, on the data
files given, in three units of length (the first picture a new user gets, and whether it
depends on the units).

For each file and each of "Ray-Traced Spheres", "RBF Volume", "SPH Volume" and "SPH
Fluid", at the scales 1e-3, 1 and 1e3 (points and arrays in the other units as
Testing/Python/raymappers_scales.py says; the camera reset, the colour map rescaled to the
array's range) it measures: the fraction of the pixels that differ from the background (by
more than 8 of 255 in a channel), the rmse (of 255) of the picture against the one at 1, the
size array the representation picked and the size in use (the ...InUse property), and the
time of the first still render (Render() after Show and ColorBy: the data's delivery, the
mapper's build and the frame). Writes one CSV row per file, representation and scale, a
markdown table per file and representation, and the pictures at scale 1 as
<images>/<file stem>-<representation>.png.

usage: pvpython defaults_on_data.py --plugin RayMappers.so [--size W H] --csv OUT.csv
           --markdown OUT.md --images DIR FILE[:ARRAY] ...
  FILE    legacy VTK polydata of particles (the project's generators write these)
  ARRAY   the point array to colour by (default: the first of COLOR_NAMES the file has)
"""
import argparse
import csv
import os
import sys
import tempfile

from paraview.simple import CreateView, Delete, LoadPlugin

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'Python'))
from raymappers_scales import (REPRESENTATIONS, SCALES, drawn_fraction, picture,  # noqa: E402
                               producer, read_particles)
from raymappers_testing import prepare_view, rmse  # noqa: E402

BACKGROUND = [0.1, 0.1, 0.15]
# The arrays a user would colour by first: speeds, then energies, then counts.
COLOR_NAMES = ('vmag', 'speed', 'v_speed', 'c_pe', 'c_contacts')
FIELDS = ('file', 'points', 'color', 'representation', 'scale', 'drawn_fraction',
          'rmse_vs_1', 'size_array', 'size_in_use', 'size_ratio_vs_1', 'first_render_s')


def arguments():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--plugin', required=True)
    parser.add_argument('--size', type=int, nargs=2, default=[400, 300])
    parser.add_argument('--csv', required=True)
    parser.add_argument('--markdown', required=True)
    parser.add_argument('--images', required=True)
    parser.add_argument('files', nargs='+', metavar='FILE[:ARRAY]')
    return parser.parse_args()


def measure(view, path, color, size, images, scratch):
    """The CSV rows of one file: every representation at every scale."""
    points, arrays = read_particles(path)
    if color is None:
        color = next((name for name in COLOR_NAMES if name in arrays), None)
    if color not in arrays:
        sys.exit('%s: no point array %s to colour by (has %s)' % (path, color, sorted(arrays)))
    stem = os.path.splitext(os.path.basename(path))[0]
    rows = []
    for kind in REPRESENTATIONS:
        name = kind[0].replace(' ', '')
        shots = {s: picture(view, producer(points, arrays, s), kind, color,
                            os.path.join(images if s == 1.0 else scratch,
                                         '%s-%s%s.png' % (stem, name, '' if s == 1.0 else s)),
                            size) for s in SCALES}
        for s in SCALES:
            shot = shots[s]
            rows.append({'file': os.path.basename(path), 'points': len(points), 'color': color,
                         'representation': kind[0], 'scale': s,
                         'drawn_fraction': drawn_fraction(shot['image'], BACKGROUND),
                         'rmse_vs_1': rmse(shot['image'], shots[1.0]['image']),
                         'size_array': shot['array'], 'size_in_use': shot['size'],
                         'size_ratio_vs_1': shot['size'] / shots[1.0]['size'] / s
                         if shots[1.0]['size'] else float('nan'),
                         'first_render_s': shot['seconds']})
            print('%s %s x%g: drawn %.1f%%, rmse %.2f, size %s %.6g, %.3f s'
                  % (stem, kind[0], s, 100 * rows[-1]['drawn_fraction'], rows[-1]['rmse_vs_1'],
                     shot['array'], shot['size'], shot['seconds']), flush=True)
    return rows


def markdown(rows, size):
    """One line per file and representation: the scale-1 values and each scale's rmse."""
    lines = ['| data | representation | size array | size in use (x1) | size x1e-3, x1e3 '
             '(/ scale, / x1) | drawn x1e-3 / x1 / x1e3 | rmse x1e-3, x1e3 (of 255) | '
             'first render x1 |', '|---|---|---|---|---|---|---|---|']
    for unit in (r for r in rows if r['scale'] == 1.0):
        same = [r for r in rows if (r['file'], r['representation'])
                == (unit['file'], unit['representation'])]
        by_scale = {r['scale']: r for r in same}
        lines.append('| %s (%d points, colour %s) | %s | %s | %.4g | %.6f, %.6f | %s | %s | '
                     '%.0f ms |' % (
                         unit['file'], unit['points'], unit['color'], unit['representation'],
                         unit['size_array'], unit['size_in_use'],
                         by_scale[1e-3]['size_ratio_vs_1'], by_scale[1e3]['size_ratio_vs_1'],
                         ' / '.join('%.1f%%' % (100 * by_scale[s]['drawn_fraction'])
                                    for s in SCALES),
                         ', '.join('%.2f' % by_scale[s]['rmse_vs_1'] for s in (1e-3, 1e3)),
                         1000 * unit['first_render_s']))
    return '\n'.join(lines) + '\n\n%dx%d pixels; drawn: pixels more than 8/255 from the ' \
        'background.\n' % tuple(size)


def main():
    args = arguments()
    LoadPlugin(args.plugin, remote=False, ns=globals())
    view = CreateView('RenderView')
    prepare_view(view, args.size, BACKGROUND)
    os.makedirs(args.images, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for item in args.files:
            path, _, color = item.partition(':')
            rows += measure(view, path, color or None, args.size, args.images, scratch)
    Delete(view)
    with open(args.csv, 'w', newline='') as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    with open(args.markdown, 'w') as f:
        f.write(markdown(rows, args.size))
    print(markdown(rows, args.size))
    return 0


if __name__ == '__main__':
    sys.exit(main())
