# Strong scaling under yade.mpy: one scene, serial and on 2 and 3 MPI ranks (mpy's master plus one
# or two workers), cost per particle-step.  The lattice of bench/scaling.py (touching spheres on a
# floor, every neighbour contact a bridge, μ = 1 Pa·s, Adams–Perchard + slip), the full
# viscbridge.engines() list (time stepper and guard included), split into slabs along x.
#
#   ./yadew run bench/mpi_scaling.py [INTEGRATION:SIDE:STEPS ...]
# (default explicit:20:100 explicit:30:40 implicit:10:20; SIDE³ spheres) drives one run per case and
# rank count and writes docs/perf/mpi_scaling.csv.  One thread per rank (OMP_NUM_THREADS=1).
import csv
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
sys.path.insert(0, HERE)
import common  # noqa: E402
OUT = os.path.join(HERE, '..', 'docs', 'perf', 'mpi_scaling.csv')
R = 0.5e-3
WARMUP = 5


def lattice(n_side, integration):
    from yade import O, utils
    import yade.wrapper as yw
    import viscbridge
    mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
    pitch = 2 * R * (1 - 1e-4)  # touching, 0.01 % overlap
    O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))
    O.bodies.append([utils.sphere((i * pitch, j * pitch, R * (1 - 1e-4) + k * pitch), R, material=mat)
                     for i in range(n_side) for j in range(n_side) for k in range(n_side)])
    O.engines = viscbridge.engines(viscosity=1.0, normalModel='adamsPerchard', tangentialModel='slip', integration=integration)
    O.dt = 1e-9


def worker(n_side, integration, steps, out):
    from yade import O
    import viscbridge.mpi
    distributed = 'OMPI_COMM_WORLD_SIZE' in os.environ
    lattice(n_side, integration)
    viscbridge.mpi.decompose(axis=0)
    if distributed:
        from yade import mpy as mp
        run = lambda n: mp.mpirun(n, mp.numThreads)  # noqa: E731
    else:
        run = lambda n: O.run(n, True)  # noqa: E731
    run(WARMUP)  # includes mpy's split (serialising and sending the scene)
    t0 = time.perf_counter()
    run(steps)
    seconds = time.perf_counter() - t0
    if viscbridge.mpi.rank() == 0:
        n = n_side ** 3
        json.dump(dict(integration=integration, spheres=n, ranks=viscbridge.mpi.ranks(), steps=steps, seconds_per_step=seconds / steps,
                       microseconds_per_particle_step=seconds / steps / n * 1e6), open(out, 'w'))


if len(sys.argv) > 1 and sys.argv[1] == '--worker':
    worker(int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), sys.argv[5])
else:
    cases = [a.split(':') for a in sys.argv[1:]] or [['explicit', '20', '100'], ['explicit', '30', '40'], ['implicit', '10', '20']]
    ROUNDS = 3  # the VM is noisy and MPI steps wait for the slowest rank: the fastest of interleaved rounds

    def measure(integration, n_side, steps, ranks):
        return common.run_on_ranks(os.path.join(HERE, 'mpi_scaling.py'), ['--worker', n_side, integration, steps], ranks)

    runs = {}
    for _ in range(ROUNDS):
        for integration, n_side, steps in cases:
            for ranks in (1, 2, 3):
                row = measure(integration, n_side, steps, ranks)
                runs.setdefault((integration, n_side, ranks), []).append(row)
                print(row, flush=True)
    rows = []
    for integration, n_side, steps in cases:
        for ranks in (1, 2, 3):
            all_runs = sorted(runs[(integration, n_side, ranks)], key=lambda r: r['seconds_per_step'])
            row = dict(all_runs[0], rounds=len(all_runs), slowest_seconds_per_step=all_runs[-1]['seconds_per_step'])
            serial = min(r['seconds_per_step'] for r in runs[(integration, n_side, 1)])
            row['speedup'] = serial / row['seconds_per_step']
            rows.append(row)
    with open(OUT, 'w', newline='') as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print('wrote', OUT)
