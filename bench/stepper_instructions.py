#!/usr/bin/env python3
"""What ViscBridgeTimeStepper costs, in instructions (valgrind/callgrind): the study's wetted bed
(300 spheres, μ = 1 Pa·s) saved after 100 steps, then run for STEPS steps with the stepper on and
with it `dead` (same engines, same Δt), counting every instruction of the steps.  Repeatable to the
instruction, unlike the wall-clock on/off of stepper_cost.py on a shared machine.

    ./yadew sh python3 bench/stepper_instructions.py [STEPS]      (default 2060; ~5 min)
"""
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
steps = int(sys.argv[1]) if len(sys.argv) > 1 else 2060

PREPARE = """
import sys
sys.path.insert(0, %r)
import common
from yade import O
import viscbridge.scan as scan
case = scan.normalize_case(dict(n=300, seed=5, viscosity=1.0))
scan._Trial(case, scan.dry_bed(case, common.CACHE)).prepare()
O.run(100, True)
O.save(sys.argv[1])
""" % HERE

RUN = """
import sys
from yade import O
import yade.wrapper as yw
O.load(sys.argv[1])
ts = next(e for e in O.engines if isinstance(e, yw.ViscBridgeTimeStepper))
ts.dead = sys.argv[2] == 'off'
updates = ts.updates
O.run(%d, True)
print('full updates', ts.updates - updates)
""" % steps


def instructions(tmp, run, saved, config):
    out = subprocess.run(['valgrind', '--tool=callgrind', '--callgrind-out-file=' + os.path.join(tmp, config + '.cg'),
                          '--toggle-collect=yade::Scene::moveToNextTimeStep()', 'yade', '-n', '-x', run, saved, config],
                         capture_output=True, text=True)
    updates = re.findall(r'full updates (\d+)', out.stdout)
    if out.returncode != 0 or not updates:
        sys.exit('stepper_instructions: the %s run failed:\n%s' % (config, out.stderr[-2000:]))
    return int(re.findall(r'I\s+refs:\s+([\d,]+)', out.stderr)[-1].replace(',', '')), int(updates[0])


with tempfile.TemporaryDirectory() as tmp:
    prepare, run, saved = (os.path.join(tmp, name) for name in ('prepare.py', 'run.py', 'bed.yade.gz'))
    open(prepare, 'w').write(PREPARE)
    open(run, 'w').write(RUN)
    subprocess.run(['yade', '-n', '-x', prepare, saved], check=True, capture_output=True)
    on, updates = instructions(tmp, run, saved, 'on')
    off, _ = instructions(tmp, run, saved, 'off')
print('study bed, %d steps: stepper on %d instructions (%d full updates), off %d: %+.1f %% of a step'
      % (steps, on, updates, off, 100.0 * (on - off) / off))
