"""One case of a viscbridge scan: the job script of the scan's yade-batch table and of its Slurm array
job (``YADE_BATCH=<table>:<line> yade -n -x job.py``).  The line selects the case; its result is
appended to ``<scanDir>/results.jsonl``, and a case already there is skipped.  See
:mod:`viscbridge.scan`.  Importing this module runs nothing.
"""
import os

__all__ = ['main']


def main():
    """Run the case of the yade-batch table line in YADE_BATCH (inside YADE)."""
    from yade import utils
    import viscbridge.scan as scan
    utils.readParamsFromTable(noTableOk=False, scanDir='.', **scan.CASE_DEFAULTS)
    from yade.params import table
    case = scan.normalize_case({k: getattr(table, k) for k in scan.CASE_DEFAULTS})
    results = scan.ResultsFile(os.path.join(table.scanDir, 'results.jsonl'))
    # a resubmitted Slurm array runs every line of the whole scan again: finished cases end at once
    if scan.case_key(case) in results.done_keys():
        print('case %s is already in %s: skipped' % (scan.case_key(case), results.path))
        return
    result = scan.find_critical_dt(case, os.path.join(table.scanDir, 'beds'))
    results.append(result)
    print('critical dt %.4g s (stable %.4g, unstable %.4g), stepper %.4g s' % (
        result['dt_critical'], result['dt_stable'], result['dt_unstable'], result['dt_stepper']))


if __name__ == '__main__':  # `yade -n -x job.py` runs the script in YADE's __main__
    main()
