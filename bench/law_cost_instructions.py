#!/usr/bin/env python3
"""Instruction counts of InteractionLoop (valgrind/callgrind) for the configurations of
law_cost.py: repeatable to the instruction, unlike wall-clock times on a shared machine.

    ./yadew sh python3 bench/law_cost_instructions.py [N]      (default 1000 spheres; ~10 min)
"""
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import common  # noqa: E402
from common import CONFIGS  # noqa: E402

n = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
SCRIPT = """
import sys
sys.path.insert(0, %r)
import common
from yade import O
common.load(common.bed(%d), sys.argv[1])
O.run(20, True)
O.run(40, True)
""" % (HERE, n)

rows = []
with tempfile.TemporaryDirectory() as tmp:
    script = os.path.join(tmp, 'run.py')
    open(script, 'w').write(SCRIPT)
    subprocess.run(['yade', '-n', '-x', script, 'yade_mindlin'], check=True, capture_output=True)  # builds the bed
    counts = {}
    for config in CONFIGS:
        out = subprocess.run(['valgrind', '--tool=callgrind', '--callgrind-out-file=' + os.path.join(tmp, config + '.cg'),
                              "--toggle-collect=yade::InteractionLoop::action()", 'yade', '-n', '-x', script, config],
                             capture_output=True, text=True)
        counts[config] = int(re.findall(r'I\s+refs:\s+([\d,]+)', out.stderr)[-1].replace(',', ''))
        print('%-28s %14d instructions  %.3f' % (config, counts[config], counts[config] / counts['yade_mindlin']), flush=True)
        rows.append(dict(spheres=n, configuration=config, instructions=counts[config],
                         ratio_to_yade_mindlin=counts[config] / counts['yade_mindlin']))
    # where the interaction loop spends its instructions with every effect on, and in YADE's law
    for config in ('vb_all', 'yade_mindlin'):
        annotated = subprocess.run(['callgrind_annotate', '--inclusive=no', os.path.join(tmp, config + '.cg')],
                                   capture_output=True, text=True, check=True).stdout
        path = os.path.join(common.RESULTS, 'profile_interaction_loop_%s.txt' % config)
        with open(path, 'w') as fh:
            fh.write('# callgrind_annotate (self cost) of InteractionLoop::action(), %d spheres, 40 steps, %s\n' % (n, config))
            fh.write('\n'.join(annotated.splitlines()[:60]) + '\n')
        print('written', path)
print('written', common.write_rows(os.path.join(common.RESULTS, 'law_cost_instructions.csv'), rows))
