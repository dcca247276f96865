#!/usr/bin/env python3
"""The scaling table of distributed rendering: each RayMappers representation rendered by
pvbatch on 1, 2 and 3 MPI ranks (Testing/Python/distributed_scene.py: the data split by
ParaView's kd-tree redistribution, IceT compositing), median wall time of the still renders
after the first, on rank 0 (so compositing included).

usage: distributed_scaling.py --build BUILD [--particles FILE] [--ranks 1 2 3]
         [--repeat 5] [--size 800 600] [--csv OUT.csv] [--markdown OUT.md]
Run it with /usr/bin/python3 (not pvpython: pvpython is an MPI process itself and a nested
mpirun fails), under Xvfb.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
SCENES = ('spheres', 'rbf', 'sph', 'zsweep', 'fluid')


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--build', required=True)
    parser.add_argument('--particles', default='',
                        help='particle file (default: the bundled coarse dam break)')
    parser.add_argument('--scenes', nargs='+', default=list(SCENES), choices=SCENES)
    parser.add_argument('--ranks', type=int, nargs='+', default=[1, 2, 3])
    parser.add_argument('--repeat', type=int, default=5)
    parser.add_argument('--size', type=int, nargs=2, default=[800, 600])
    parser.add_argument('--csv', default='')
    parser.add_argument('--markdown', default='')
    args = parser.parse_args()

    plugin = os.path.join(args.build, 'lib', 'paraview-plugins', 'RayMappers', 'RayMappers.so')
    launcher = os.path.join(args.build, 'bin', 'raymappers-env')
    scene_script = os.path.join(root, 'Testing', 'Python', 'distributed_scene.py')
    env = {k: v for k, v in os.environ.items() if not k.startswith(('OMPI_', 'PMIX_', 'OPAL_'))}
    rows = []
    for scene in args.scenes:
        for ranks in args.ranks:
            command = [launcher, 'mpirun', '--allow-run-as-root', '--oversubscribe', '-x',
                       'LD_PRELOAD', '-np', str(ranks), 'pvbatch', scene_script,
                       '--plugin', plugin, '--data-dir', os.path.join(root, 'Data'),
                       '--representation', scene, '--repeat', str(args.repeat + 1),
                       '--size', str(args.size[0]), str(args.size[1]),
                       '--output', os.path.join(args.build, 'Testing', 'Temporary',
                                                'scaling-%s-%d.png' % (scene, ranks))]
            if args.particles and scene != 'zsweep':
                command += ['--fine', args.particles]
            done = subprocess.run(command, capture_output=True, text=True, env=env)
            lines = [l for l in done.stdout.splitlines() if l.startswith('{')]
            if done.returncode != 0 or not lines:
                sys.stderr.write(done.stderr[-3000:])
                raise SystemExit('%s on %d ranks failed' % (scene, ranks))
            result = json.loads(lines[-1])
            row = {'representation': scene, 'ranks': ranks, 'points': result['points'],
                   'cells': result['cells'], 'first_frame_ms': 1000 * result['first_render_s'],
                   'median_frame_ms': 1000 * result['median_render_s']}
            rows.append(row)
            print('%-8s %d ranks: %9.1f ms median, first %9.1f ms' % (
                scene, ranks, row['median_frame_ms'], row['first_frame_ms']), flush=True)

    if args.csv:
        with open(args.csv, 'w', newline='') as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    table = ['| representation | data | ' + ' | '.join('%d rank%s' % (r, 's' if r > 1 else '')
                                                      for r in args.ranks) +
             ' | speed-up at %d |' % args.ranks[-1],
             '|---|---|' + '---|' * (len(args.ranks) + 1)]
    for scene in args.scenes:
        mine = [r for r in rows if r['representation'] == scene]
        base = mine[0]['median_frame_ms']
        data = ('%d cells' % mine[0]['cells']) if scene == 'zsweep' else (
            '%d particles' % mine[0]['points'])
        table.append('| %s | %s | %s | %.2fx |' % (
            scene, data, ' | '.join('%.0f ms' % r['median_frame_ms'] for r in mine),
            base / mine[-1]['median_frame_ms']))
    print('\n'.join(table))
    if args.markdown:
        with open(args.markdown, 'w') as f:
            f.write('\n'.join(table) + '\n')


if __name__ == '__main__':
    main()
