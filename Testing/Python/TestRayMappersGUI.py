"""The GUI test: plays Testing/XML/TestRayMappersGUI.xml in the paraview client through
ParaView's smTestDriver, then checks the screenshots the playback took (raymappers_gui.shot,
from ParaView's Python shell) with the project's image comparison (raymappers-compare-images,
the same as the C++ and pvpython tests'):
- the four pictures (spheres with the typed radius, RBF, SPH and Z-Sweep volumes) match their
  baselines under their thresholds (Testing/Data/Baseline/thresholds.txt);
- the three emptied views (top opacity 0 in the opacity table) are uniformly the
  background, and the pictures before the edits are not;
- a check of the check: the SPH volume with the top opacity typed as 0.9 instead of 1 does
  NOT match the baseline of opacity 1;
- Select Points On dragged over the spheres selected points, and the shot after it shows
  magenta (the selection colour) where the shot before it shows none;
- the spheres with Opacity By Array checked match the independent reference of the
  translucent spheres (raymappers-reference, written by the playback), and differ from the
  opaque spheres; unchecked again they match the opaque baseline.

usage: pvpython TestRayMappersGUI.py --driver SMTESTDRIVER --client PARAVIEW --plugin-dir DIR
         --data DIR --baselines DIR --output DIR --script XML --compare TOOL
         --reference TOOL
"""
import argparse
import json
import os
import subprocess
import sys

parser = argparse.ArgumentParser()
for name in ('driver', 'client', 'plugin-dir', 'data', 'baselines', 'output', 'script', 'compare',
             'reference'):
    parser.add_argument('--' + name, required=True)
args = parser.parse_args()

MATCHED = ['TestRayMappersGUI', 'TestRayMappersGUI_RBFVolume', 'TestRayMappersGUI_SPHVolume',
           'TestRayMappersGUI_ZSweepVolume']
EMPTIED = ['TestRayMappersGUI_RBFEmpty', 'TestRayMappersGUI_SPHEmpty',
           'TestRayMappersGUI_ZSweepEmpty']
NEGATIVE = ('TestRayMappersGUI_SPHVolume_opacity09', 'TestRayMappersGUI_SPHVolume')
TRANSLUCENT = 'TestRayMappersGUI_SpheresOpacityByArray'
OPAQUE_AGAIN = ('TestRayMappersGUI_SpheresOpaqueAgain', 'TestRayMappersGUI')
# (rmse, differing fraction, tolerance, max error) of the translucent spheres against their
# reference: 8-bit blending rounds (Rendering.TestSpheresTranslucency's rmse bound), and a few
# grazed silhouettes of the dam break's dense spheres, where float and double disagree on a hit,
# differ by more (measured: rmse 0.46, 2 of 90000 pixels beyond 2 levels, the worst by 20).
TRANSLUCENT_BOUND = ('0.75', '0.0005', '2', '255')

failures = []


def run(command, expect=0, what=''):
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(result.stdout.rstrip())
    ok = result.returncode == expect
    print(('ok    ' if ok else 'FAIL  ') + what)
    if not ok:
        failures.append(what)


# The shots go where the perturbation check of all baselines reads the tests' pictures.
shots = args.output
SELECTION = 'TestRayMappersGUI_Selection'
for name in MATCHED + EMPTIED + [NEGATIVE[0], SELECTION, TRANSLUCENT, TRANSLUCENT + '-reference',
                                  OPAQUE_AGAIN[0]]:
    for path in (os.path.join(shots, name + '.png'), os.path.join(shots, name + '.json')):
        if os.path.exists(path):
            os.remove(path)

# The client must not inherit pvpython's MPI singleton (its Open MPI / PMIx variables).
env = {k: v for k, v in os.environ.items()
       if not k.startswith(('OMPI_', 'PMIX_', 'OPAL_', 'PRTE_'))}
env['RAYMAPPERS_GUI_OUTPUT'] = shots
env['RAYMAPPERS_TESTING_PYTHON'] = os.path.dirname(os.path.abspath(__file__))
env['RAYMAPPERS_REFERENCE'] = args.reference
playback = subprocess.run(
    [args.driver, '--client', args.client, '--dr', '--plugin-search-paths=' + args.plugin_dir,
     '--plugins=RayMappers', '--data-directory=' + args.data,
     '--baseline-directory=' + args.baselines, '--test-directory=' + args.output,
     '--test-script=' + args.script, '--exit'], env=env)
if playback.returncode != 0:
    failures.append('the playback (exit code %d)' % playback.returncode)
    print('FAIL  the playback of %s exited with %d' % (args.script, playback.returncode))


def shot(name):
    return os.path.join(shots, name + '.png')


for name in MATCHED:
    run([args.compare, shot(name), os.path.join(args.baselines, name + '.png')],
        what='%s matches its baseline' % name)
for name in EMPTIED:
    run([args.compare, '--uniform', shot(name)], what='%s is only the background' % name)
for name in MATCHED[1:]:
    run([args.compare, '--uniform', shot(name)], expect=1, what='%s is not empty' % name)
run([args.compare, '--expect-difference', shot(NEGATIVE[0]),
     os.path.join(args.baselines, NEGATIVE[1] + '.png')],
    what='the top opacity 0.9 does not pass for the baseline of opacity 1')

run([args.compare, '--bound'] + list(TRANSLUCENT_BOUND) + [shot(TRANSLUCENT),
                                                         shot(TRANSLUCENT + '-reference')],
    what='Opacity By Array: the spheres match their translucent reference')
run([args.compare, '--expect-difference', shot(TRANSLUCENT),
     os.path.join(args.baselines, 'TestRayMappersGUI.png')],
    what='Opacity By Array changes the picture of the opaque spheres')
run([args.compare, shot(OPAQUE_AGAIN[0]), os.path.join(args.baselines, OPAQUE_AGAIN[1] + '.png')],
    what='Opacity By Array unchecked: the opaque spheres again')


def magenta_pixels(png):
    from raymappers_testing import pixels
    rgb = pixels(png)
    return int(((rgb[:, 0] > rgb[:, 1] + 60) & (rgb[:, 2] > rgb[:, 1] + 60)).sum())


def check_selection():
    report = os.path.join(shots, SELECTION + '.json')
    selected = json.load(open(report))['selected_points'] if os.path.exists(report) else []
    before, after = magenta_pixels(shot(MATCHED[0])), magenta_pixels(shot(SELECTION))
    ok = len(selected) > 0 and after > 50 and before == 0
    print(('ok    ' if ok else 'FAIL  ') + 'Select Points On selected %d spheres; magenta pixels '
          '%d after, %d before' % (len(selected), after, before))
    if not ok:
        failures.append('the selection')


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
if os.path.exists(shot(SELECTION)) and os.path.exists(shot(MATCHED[0])):
    check_selection()
else:
    failures.append('the selection shot')
    print('FAIL  no selection shot')
print('%d check(s) failed' % len(failures) if failures else 'all checks passed')
sys.exit(1 if failures else 0)
