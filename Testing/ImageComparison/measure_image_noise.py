"""Measures the run-to-run noise of every image test, from which the thresholds in
Testing/Data/Baseline/thresholds.txt are set: each image ctest is run ROUNDS times, in
alternating conditions (all cores; one core through taskset, so TBB runs one thread; and for
the ParaView tests RAYMAPPERS_THREADS=1), its pictures kept, and every later picture compared
with the first (raymappers-compare-images --measure). Prints, per baseline, the largest rmse,
max error and differing fraction (tolerance 2) over the runs, and the same against the
committed baseline.

usage: python3 measure_image_noise.py BUILD_DIR [--rounds N] [--only REGEX]
(run under xvfb-run; takes a few minutes per round)
"""
import argparse
import glob
import os
import re
import shutil
import subprocess
import tempfile

parser = argparse.ArgumentParser()
parser.add_argument('build')
parser.add_argument('--rounds', type=int, default=4)
parser.add_argument('--only', default='')
args = parser.parse_args()

source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
baselines = os.path.join(source, 'Testing', 'Data', 'Baseline')
temporary = os.path.join(args.build, 'Testing', 'Temporary')
tool = os.path.join(args.build, 'bin', 'raymappers-compare-images')
names = sorted(os.path.basename(p)[:-4] for p in glob.glob(os.path.join(baselines, '*.png')))


def ctest_of(name):
    if name.startswith('TestRayMappersGUI'):
        return 'GUI.TestRayMappersGUI'
    if 'Representation' in name:
        return 'Python.' + name
    return 'Rendering.' + name


def measure(a, b):
    out = subprocess.run([tool, '--measure', a, b], stdout=subprocess.PIPE, text=True).stdout
    line = [l for l in out.splitlines() if l.startswith('tolerance 2:')]
    if not line:
        return None
    rmse, worst, differing = re.findall(r'[-0-9.]+', line[0])[1:4]
    return float(rmse), int(worst), float(differing)


conditions = [('all cores', [], {}), ('one core', ['taskset', '-c', '0'],
                                      {'RAYMAPPERS_THREADS': '1'})]
keep = tempfile.mkdtemp(prefix='image-noise-')
tests = sorted(set(ctest_of(n) for n in names if re.search(args.only, n)))
for r in range(args.rounds):
    label, prefix, extra = conditions[r % len(conditions)]
    env = dict(os.environ, **extra)
    for t in tests:
        subprocess.run(prefix + ['ctest', '-R', '^%s$' % re.escape(t)], cwd=args.build, env=env,
                       stdout=subprocess.DEVNULL)
    for n in names:
        if os.path.exists(os.path.join(temporary, n + '.png')):
            shutil.copy(os.path.join(temporary, n + '.png'), os.path.join(keep, '%s.%d.png' % (n, r)))
    print('round %d (%s) done' % (r, label), flush=True)

print('%-44s %26s %26s' % ('baseline', 'noise: rmse max differing', 'vs baseline'))
for n in names:
    first = os.path.join(keep, '%s.0.png' % n)
    if not os.path.exists(first):
        continue
    noise = [measure(first, os.path.join(keep, '%s.%d.png' % (n, r))) for r in range(1, args.rounds)]
    noise = [m for m in noise if m]
    worst = tuple(max(m[i] for m in noise) for i in range(3)) if noise else (0, 0, 0)
    base = measure(first, os.path.join(baselines, n + '.png')) or (-1, -1, -1)
    print('%-44s %8.4f %4d %10.5f%% %8.4f %4d %10.5f%%' % ((n,) + worst + base))
