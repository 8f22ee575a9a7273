"""The yade-batch table of a scan (one line per case; also what the Slurm array job runs) and the job
script that runs one line of it (:data:`JOB_SCRIPT`).  Plain Python.
"""
import os
import re

from .cases import CASE_DEFAULTS, case_key, unique_cases

__all__ = ['JOB_SCRIPT', 'write_table']

#: The job script of the table: ``YADE_BATCH=<table>:<line> yade -n -x JOB_SCRIPT`` runs one case.
JOB_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'job.py')


def _table_value(v):
    return repr(v) if isinstance(v, str) else ('%r' % v)


def write_table(cases, path, scan_dir):
    """A yade-batch table: one line per case (columns: every case field, plus scanDir).  Every case
    is checked before the file is touched, and the file is replaced whole."""
    fields = list(CASE_DEFAULTS)
    scan_dir = os.path.abspath(scan_dir)
    if re.search(r'\s', scan_dir):  # the table's columns are separated by white space
        raise ValueError('scan directory %r: a path with white space cannot go into a yade-batch table' % scan_dir)
    lines = [' '.join(['description'] + fields + ['scanDir'])]
    for c in unique_cases(cases):
        lines.append(' '.join([case_key(c)] + [_table_value(c[f]) for f in fields] + [repr(scan_dir)]))
    tmp = path + '.part'
    with open(tmp, 'w') as fh:
        fh.write('\n'.join(lines) + '\n')
    os.replace(tmp, path)
    return path
