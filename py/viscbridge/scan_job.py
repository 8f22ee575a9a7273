# One case of a viscbridge scan: the job script of the scan's yade-batch table (and of its Slurm
# array job).  YADE_BATCH=<table>:<line> selects the case; the result is appended to
# <scanDir>/results.jsonl.  See viscbridge.scan.
import os

from yade import utils

import viscbridge.scan as scan

utils.readParamsFromTable(noTableOk=False, scanDir='.', **scan.CASE_DEFAULTS)
from yade.params import table  # noqa: E402

case = {k: getattr(table, k) for k in scan.CASE_DEFAULTS}
result = scan.find_critical_dt(case, os.path.join(table.scanDir, 'beds'))
scan.ResultsFile(os.path.join(table.scanDir, 'results.jsonl')).append(result)
print('critical dt %.4g s (stable %.4g, unstable %.4g), stepper %.4g s' % (
    result['dt_critical'], result['dt_stable'], result['dt_unstable'], result['dt_stepper']))
