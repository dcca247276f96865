"""ctest: on several MPI ranks the interactive renders of a time-critical RayMappers volume
(Z-Sweep, SPH Volume) draw at one image sample distance on every rank.

Each rank's mapper chooses an interactive frame's distance from its own last frame's time
against the frame budget (vtkRayMapperCore::BeginFrame): left alone, the ranks of unequal
pieces or unequal times draw their parts of one image at different resolutions. The
representations give every rank the slowest one's last frame before each render
(vtkRayMapperPropRepresentation::ShareLastFrame).

Runs this file under `mpirun -np N pvbatch --symmetric` (every rank runs the scene and
prints its own mapper's counters), then checks:
- every rank reports each render;
- in each interactive render all ranks have the same image_sample_distance_percent, and the
  budget binds (some distance above 1, none at the maximum after the first, so that equal
  distances are not merely the clamp's);
- the still render after them is exact (distance 1) on every rank.
With ShareLastFrame removed, 2 ranks fail (2026-12-07): Z-Sweep in all four interactive
renders (2.29 / 2.23, 1.48 / 1.33, ...), SPH Volume in renders 2-4 (2.58 / 2.87, ...; its
first one sat at the clamp, 4.00, on both ranks); earlier runs had SPH failing all four
(2.12 / 2.13, ...) and Z-Sweep the last two (1.10 / 1.07); in a run without
the test's budget, of disk_out_ref unbalanced, 1.86 / 2.03 and 1.16 / 1.30.

usage: pvpython TestDistributedSampleDistance.py --launcher RAYMAPPERS_ENV --plugin PLUGIN
         --data-dir DATA --representation zsweep|sph --ranks N
"""
import argparse
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, failures  # noqa: E402

INTERACTIVE_RENDERS = 4
# name: (representation, statistics property, budget property, budget s, maximum distance)
SCENES = {'zsweep': ('Z-Sweep Volume', 'ZSweepRenderStatistics', 'ZSweepFrameBudget', 0.05, 9.0),
          'sph': ('SPH Volume', 'SPHRenderStatistics', 'SPHFrameBudget', 0.015, 4.0)}


def scene(args):
    """One rank's part (under pvbatch --symmetric): a still render, interactive renders at a
    budget below the frame's time, a still render; one JSON line of its distances."""
    from paraview import servermanager, simple
    simple.LoadPlugin(args.plugin, remote=False, ns=globals())
    name, statistics, budget, seconds, _ = SCENES[args.representation]
    if args.representation == 'zsweep':
        reader = simple.ExodusIIReader(FileName=[args.data_dir + '/disk_out_ref.ex2'])
        reader.PointVariables = ['Temp']
        source, array = simple.MergeBlocks(Input=reader), 'Temp'
    else:
        source = simple.LegacyVTKReader(FileNames=[args.data_dir + '/dam_break_coarse_00674.vtk'])
        array = 'vmag'
    view = simple.CreateView('RenderView')
    view.ViewSize = [400, 300]
    rep = simple.Show(simple.RedistributeDataSet(Input=source), view)
    rep.SetRepresentationType(name)
    simple.ColorBy(rep, ('POINTS', array))
    if args.representation == 'sph':
        rep.SPHKernel = 'Wendland C2'
        rep.SPHSmoothingLengthArray = ['POINTS', 'h']
        rep.SPHMassArray = ['POINTS', 'm']
        rep.SPHDensityArray = ['POINTS', 'rho']
    rep.SetPropertyWithName(budget, seconds)

    def distance():
        rep.UpdatePropertyInformation()
        for line in rep.GetPropertyValue(statistics).splitlines():
            if line.startswith('counter image_sample_distance_percent '):
                return int(line.split()[-1])
        return None

    simple.Render(view)
    distances = {'still_first': distance(), 'interactive': []}
    for _ in range(INTERACTIVE_RENDERS):
        view.InteractiveRender()
        distances['interactive'].append(distance())
    view.StillRender()
    distances['still_last'] = distance()
    distances['rank'] = servermanager.vtkProcessModule.GetProcessModule().GetPartitionId()
    print('DISTANCES ' + json.dumps(distances), flush=True)
    simple.Delete(view)


def arguments():
    parser = argparse.ArgumentParser()
    parser.add_argument('--launcher')
    parser.add_argument('--plugin', required=True)
    parser.add_argument('--data-dir', required=True)
    parser.add_argument('--representation', required=True, choices=sorted(SCENES))
    parser.add_argument('--ranks', type=int, default=2)
    parser.add_argument('--scene', action='store_true', help='run one rank\'s part')
    return parser.parse_args()


def main(args):
    command = [args.launcher, 'mpirun', '--allow-run-as-root', '--oversubscribe', '-x',
               'LD_PRELOAD', '-np', str(args.ranks), 'pvbatch', '--symmetric',
               os.path.abspath(__file__), '--scene', '--plugin', args.plugin,
               '--data-dir', args.data_dir, '--representation', args.representation]
    print(' '.join(command))
    # pvpython itself runs as an MPI singleton; a nested mpirun must not inherit its
    # Open MPI / PMIx environment.
    env = {k: v for k, v in os.environ.items() if not k.startswith(('OMPI_', 'PMIX_', 'OPAL_'))}
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, env=env)
    sys.stderr.write(done.stderr[-4000:])
    check(done.returncode == 0, 'pvbatch on %d ranks exits cleanly (%d)'
          % (args.ranks, done.returncode))
    # mpirun forwards the ranks' output as it comes: one rank's line may run on into
    # another's (seen on 3 ranks: two objects on one line), so each object is found alone.
    ranks = [json.loads(m) for m in re.findall(r'DISTANCES (\{[^{}]*\})', done.stdout)]
    for r in sorted(ranks, key=lambda r: r['rank']):
        print('rank %d: %s' % (r['rank'], r))
    check(sorted(r['rank'] for r in ranks) == list(range(args.ranks)),
          'every rank reports (%s)' % [r['rank'] for r in ranks])
    if len(ranks) != args.ranks:
        return 1
    maximum = 100 * SCENES[args.representation][4]
    for i in range(INTERACTIVE_RENDERS):
        seen = [r['interactive'][i] for r in ranks]
        check(len(set(seen)) == 1, 'interactive render %d: one distance on all ranks (%s)'
              % (i + 1, seen))
        # The first one follows a still frame, which may take more than the budget times the
        # maximum squared (SPH on 2 ranks here: 400 on some days); the later ones follow
        # interactive frames.
        check(i == 0 or all(d is not None and d < maximum for d in seen),
              'interactive render %d: below the maximum %d (%s)' % (i + 1, maximum, seen))
    check(any(d > 100 for r in ranks for d in r['interactive']),
          'the budget binds: some interactive distance above 1')
    check(all(r['still_first'] == 100 and r['still_last'] == 100 for r in ranks),
          'the still renders are exact on every rank')
    return 1 if failures else 0


if __name__ == '__main__':
    if '--scene' in sys.argv:
        # pvbatch ends the MPI run itself: no sys.exit on the ranks.
        scene(arguments())
    else:
        sys.exit(main(arguments()))
