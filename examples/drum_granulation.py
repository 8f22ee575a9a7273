# Wet granulation in a rotating drum: agglomerates grow where wet particles meet.
#
#   ./yadew run examples/drum_granulation.py [OUTPUT_DIRECTORY] [--quick]
#
# 1000 spheres (r = 1 mm, ρ = 2500 kg/m³) fill a third of a drum (radius 25 mm, length 10 mm) that
# turns at the Froude number 0.05 (42 rpm) for three revolutions: the bed cascades.  15 % of the
# particles carry a film of a 1 Pa·s binder (2 % of their volume, liquidModel='film'): a bridge
# forms where a wet particle touches another one and takes its liquid from the films, if there is
# at least 0.2 % of a particle's volume (docs/liquid.md); the drum wall does not wet.  The viscous
# forces are implicit (the time step is the collision step).  These are viscbridge.scenes.drum's
# defaults; docs/drum.md says which parameters move the drum between regimes.
#
# Every 1/16 revolution it records the agglomerates (viscbridge.agglomerates(): connected components
# of the bridges between particles; granules: those of at least 2 spheres) and writes VTK files for
# ParaView (particles coloured by agglomerate or liquid, bridges as lines, the turning drum's facets
# and end walls; a last frame at the end of every run, docs/drum.md).  Output
# (OUTPUT_DIRECTORY, default output/drum): agglomerates.csv (a row per record, written as it is
# recorded), agglomerates.json (the drum's parameters and the columns' meanings),
# agglomerates.png (size distribution by mass at four times; granules and agglomerates, granulated
# mass fraction, granule d50 and largest, liquid CoV, breakage and coalescence, against
# revolutions; rewritten after every quarter revolution), vtk/*.vtp and vtk/*.pvd.  Runs to compare:
# python3 -m viscbridge.analysis compare DIR1 DIR2 -o cmp.png (docs/drum.md).
# Ctrl-C or SIGTERM (a batch system's time limit) stops the run: it records a last row, brings the
# PNG up to date and exits with status 130 or 143.
# Expected (measured, docs/drum.md): the agglomerates grow and break — 1000 → 384 after one
# revolution, → 210 after three, the granules holding 68 % and then 84 % of the mass, the largest
# swinging between 290 and 650 spheres as its necks break and heal; about 630 coalescences and 400
# breakages over the run.  About 9 min on one thread; where the time goes: docs/performance.md §5.
# --quick (or VISCBRIDGE_QUICK=1): 150 spheres in a smaller drum for half a revolution (the tests).
import os
import signal
import sys
import time

from yade import O

import viscbridge.scenes as scenes
import viscbridge.vtk as vtk
from viscbridge.analysis.agglomerate_history import AgglomerateHistory

sys.stdout.reconfigure(line_buffering=True)
args = [a for a in sys.argv[1:] if a != '--quick']
quick = '--quick' in sys.argv[1:] or os.environ.get('VISCBRIDGE_QUICK') == '1'
out_dir = os.path.abspath(args[0] if args else os.path.join('output', 'drum'))
os.makedirs(out_dir, exist_ok=True)

r = 1e-3
# the drum's defaults (docs/drum.md): Fr = 0.05, μ = 1 Pa·s, 15 % wetted, dry walls
if quick:
    drum = scenes.drum(radius=r, drumRadius=12 * r, n=150)
    revolutions = 0.5
else:
    drum = scenes.drum(radius=r, drumRadius=25 * r, n=1000)
    revolutions = 3.0
print(drum.describe())

history = AgglomerateHistory(os.path.join(out_dir, 'agglomerates.csv'), drum=drum)
png = os.path.join(out_dir, 'agglomerates.png')
every = drum.period / 16
O.engines = O.engines + [history.recorder(virtPeriod=every),
                         vtk.bridge_recorder(os.path.join(out_dir, 'vtk', 'drum-'), virtPeriod=every)]


def terminated(signum, frame):
    # SIGTERM (kill, a batch system's time limit) stops the run like Ctrl-C, so that what ran is kept
    raise KeyboardInterrupt('SIGTERM')


signal.signal(signal.SIGTERM, terminated)
start = time.time()
try:
    while drum.revolutions() < revolutions * (1 - 1e-9):
        drum.run(revolutions=min(0.25, revolutions - drum.revolutions()))
        row = history.record()  # the state now (the recorder's turn would come at the next step)
        history.plot(png, title=drum.describe())  # up to date after every quarter revolution
        print('%.2f revolutions (t = %.3f s, %d steps, %.0f s): %d agglomerates, %d granules holding %.0f %% of the '
              'mass, granule d50 %g, largest %d spheres, coordination %.2f' % (
                  drum.revolutions(), O.time, O.iter, time.time() - start, row['agglomerates'], row['granules'],
                  100 * row['granulated_mass_fraction'], row['granule_d50'], row['largest'], row['coordination']))
except KeyboardInterrupt as stop:
    # the interrupt reaches Python while YADE's loop may still be in a step (whose recorder may be
    # writing that step's row): let the step end before recording the state it leaves
    O.pause()
    O.wait()
    if not history.rows or history.rows[-1]['iter'] <= O.iter:  # else the recorder wrote the row of the step it cut short
        history.record()
    history.plot(png, title=drum.describe())
    print('\ninterrupted (%s) at %.3f revolutions: %d rows in %s, plotted in %s' % (
        str(stop) or 'Ctrl-C', drum.revolutions(), len(history.rows), history.csv_path, png))
    sys.exit(143 if str(stop) == 'SIGTERM' else 130)
first, last = history.rows[0], history.rows[-1]
print('agglomerates: %d → %d (granules %d → %d, %.0f %% of the mass), largest %d → %d spheres, granule d50 %g '
      '(%.0f s of wall time)' % (first['agglomerates'], last['agglomerates'], first['granules'], last['granules'],
                                 100 * last['granulated_mass_fraction'], first['largest'], last['largest'],
                                 last['granule_d50'], time.time() - start))
print('written', history.csv_path, png, os.path.join(out_dir, 'vtk'))
