"""A scan as a Slurm array job (:func:`slurm_script`): one task per line of the scan's table, each
run by the same job script as yade-batch uses.  Plain Python.
"""
import os

from .errors import ScanError
from .results import _scan_dir
from .table import JOB_SCRIPT

__all__ = ['SLURM_TEMPLATE', 'slurm_script']

#: The directory holding py/viscbridge/ (the repository, for the hint to run the job with ./yadew).
_REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

#: The Slurm batch script :func:`slurm_script` fills in (``{table}``, ``{n}``, ``{last}``,
#: ``{scan_dir}``, ``{repo}``, ``{job}``): an array job of one task per line of the scan's table.
SLURM_TEMPLATE = """#!/bin/bash
# Slurm array job for the ViscBridge scan table {table} ({n} cases).
# Every task runs one table line with the same job script yade-batch uses; results are appended to
# {scan_dir}/results.jsonl.  A task whose case is already there ends at once, so the whole array
# can simply be resubmitted after failed or cancelled tasks.
#SBATCH --job-name=viscbridge-scan
#SBATCH --array=2-{last}
#SBATCH --cpus-per-task=1
#SBATCH --time=02:00:00
#SBATCH --output={scan_dir}/slurm-%A_%a.log
export OMP_NUM_THREADS=1
# line N of the table (line 1 is the header) is the case of task N
export YADE_BATCH={table}:$SLURM_ARRAY_TASK_ID
# on the cluster, use its YADE 2025.2 with the plugin installed (cmake --install build), or:
#   {repo}/yadew run {job}
yade -n -x {job}
"""


def slurm_script(scan_dir):
    """Write scan_dir/scan.sbatch, an array job over scan_dir/cases.table (the whole scan)."""
    table = os.path.abspath(os.path.join(_scan_dir(scan_dir), 'cases.table'))
    if not os.path.exists(table):
        raise ScanError('no %s; write it with the "table" or "run" command' % table)
    with open(table) as fh:
        n = sum(1 for line in fh if line.strip()) - 1
    path = os.path.join(scan_dir, 'scan.sbatch')
    repo = _REPO
    with open(path, 'w') as fh:
        fh.write(SLURM_TEMPLATE.format(table=table, n=n, last=n + 1, scan_dir=os.path.abspath(scan_dir), job=JOB_SCRIPT, repo=repo))
    return path
