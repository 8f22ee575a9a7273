"""The yade-batch table of a scan (one line per case; also what the Slurm array job runs) and the job
script that runs one line of it (:data:`JOB_SCRIPT`).  Plain Python.
"""
import os
import re

from .cases import KINDS, case_key, kind_of, unique_cases

__all__ = ['JOB_SCRIPT', 'write_table', 'table_fields']

#: The job script of the table: ``YADE_BATCH=<table>:<line> yade -n -x JOB_SCRIPT`` runs one case.
JOB_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'job.py')


def _table_value(v):
    return repr(v) if isinstance(v, str) else ('%r' % v)


def table_fields(kind):
    """The case columns of a table of cases of `kind`: every field of the kind, after a ``kind``
    column for all but settling cases (whose tables have the columns they had before drums)."""
    return (['kind'] if kind != 'settling' else []) + list(KINDS[kind].defaults)


def write_table(cases, path, scan_dir):
    """A yade-batch table: one line per case (columns: ``kind`` unless settling, every field of the
    cases' kind, scanDir).  Every case is checked before the file is touched, and the file is
    replaced whole; the cases of one table are of one kind."""
    cases = unique_cases(cases)
    kinds = sorted({kind_of(c) for c in cases}) or ['settling']
    if len(kinds) > 1:
        raise ValueError('scan: a scan runs cases of one kind; got %s' % ' and '.join(kinds))
    fields = table_fields(kinds[0])
    scan_dir = os.path.abspath(scan_dir)
    if re.search(r'\s', scan_dir):  # the table's columns are separated by white space
        raise ValueError('scan directory %r: a path with white space cannot go into a yade-batch table' % scan_dir)
    lines = [' '.join(['description'] + fields + ['scanDir'])]
    for c in cases:
        lines.append(' '.join([case_key(c)] + [_table_value(c[f]) for f in fields] + [repr(scan_dir)]))
    tmp = path + '.part'
    with open(tmp, 'w') as fh:
        fh.write('\n'.join(lines) + '\n')
    os.replace(tmp, path)
    return path
