#!/usr/bin/env python3
"""The scaling table of distributed rendering: each RayMappers representation rendered by
pvbatch on 1 rank with 1 thread (RAYMAPPERS_THREADS=1, the serial baseline) and on 1, 2 and
3 MPI ranks with the plugin's thread choice (vtkRayMapperCore::DefaultNumberOfThreads: the cores divided among
the ranks of the machine) (Testing/Python/distributed_scene.py: the data split by
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
    # Runs: (ranks, RAYMAPPERS_THREADS or None). First one rank on one thread (the serial
    # baseline), then each rank count with the plugin's own choice (all cores for one rank,
    # the cores divided among the ranks of this machine otherwise).
    runs = [(1, 1)] + [(ranks, None) for ranks in args.ranks]
    rows = []
    for scene in args.scenes:
        for ranks, threads in runs:
            run_env = dict(env)
            exports = ['-x', 'LD_PRELOAD']
            if threads:
                run_env['RAYMAPPERS_THREADS'] = str(threads)
                exports += ['-x', 'RAYMAPPERS_THREADS']
            # --bind-to none: Open MPI binds each rank to one core by default (2 ranks or
            # fewer), which would leave a single rank one core.
            command = [launcher, 'mpirun', '--allow-run-as-root', '--oversubscribe',
                       '--bind-to', 'none'] + exports + [
                       '-np', str(ranks), 'pvbatch', scene_script,
                       '--plugin', plugin, '--data-dir', os.path.join(root, 'Data'),
                       '--representation', scene, '--repeat', str(args.repeat + 1),
                       '--size', str(args.size[0]), str(args.size[1]),
                       '--output', os.path.join(args.build, 'Testing', 'Temporary',
                                                'scaling-%s-%d.png' % (scene, ranks))]
            if args.particles and scene != 'zsweep':
                command += ['--fine', args.particles]
            done = subprocess.run(command, capture_output=True, text=True, env=run_env)
            lines = [l for l in done.stdout.splitlines() if l.startswith('{')]
            if done.returncode != 0 or not lines:
                sys.stderr.write(done.stderr[-3000:])
                raise SystemExit('%s on %d ranks failed' % (scene, ranks))
            result = json.loads(lines[-1])
            row = {'representation': scene, 'ranks': ranks,
                   'threads_per_rank': threads or 'auto', 'points': result['points'],
                   'cells': result['cells'], 'first_frame_ms': 1000 * result['first_render_s'],
                   'median_frame_ms': 1000 * result['median_render_s']}
            rows.append(row)
            print('%-8s %d ranks, threads %s: %9.1f ms median, first %9.1f ms' % (
                scene, ranks, row['threads_per_rank'], row['median_frame_ms'],
                row['first_frame_ms']), flush=True)

    if args.csv:
        with open(args.csv, 'w', newline='') as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    # The speed-up over the serial baseline at as many ranks as the machine has cores.
    cores = os.cpu_count() or 1
    at = max([r for r in args.ranks if r <= cores] or [args.ranks[0]])
    table = ['| representation | data | 1 rank, 1 thread | ' +
             ' | '.join('%d rank%s' % (r, 's' if r > 1 else '') for r in args.ranks) +
             ' | serial / %d ranks |' % at,
             '|---|---|---|' + '---|' * (len(args.ranks) + 1)]
    for scene in args.scenes:
        mine = [r for r in rows if r['representation'] == scene]
        serial = mine[0]['median_frame_ms']
        data = ('%d cells' % mine[0]['cells']) if scene == 'zsweep' else (
            '%d particles' % mine[0]['points'])
        table.append('| %s | %s | %s | %.2fx |' % (
            scene, data, ' | '.join('%.0f ms' % r['median_frame_ms'] for r in mine),
            serial / next(r for r in mine if r['ranks'] == at and r['threads_per_rank'] == 'auto')[
                'median_frame_ms']))
    print('\n'.join(table))
    if args.markdown:
        with open(args.markdown, 'w') as f:
            f.write('\n'.join(table) + '\n')


if __name__ == '__main__':
    main()
