"""One case of a viscbridge scan: the job script of the scan's yade-batch table and of its Slurm array
job (``YADE_BATCH=<table>:<line> yade -n -x job.py``).  The line selects the case — a settling case
(its critical Δt) or, in a table with ``kind`` 'drum', a drum case; its result is appended to
``<scanDir>/results.jsonl``, and a case already there is skipped.  See :mod:`viscbridge.scan`.
Importing this module runs nothing.
"""
import os

__all__ = ['main']


def _table_defaults():
    """Every column a table of any kind may have, with a default (a table holds every field of its
    kind, so only ``kind`` ever takes its default: 'settling', for tables written before drums)."""
    import viscbridge.scan as scan
    defaults = {}
    for kind in scan.KINDS.values():
        defaults.update(kind.defaults)
    return dict(defaults, kind='settling', scanDir='.')


def main():
    """Run the case of the yade-batch table line in YADE_BATCH (inside YADE)."""
    from yade import utils
    import viscbridge.scan as scan
    utils.readParamsFromTable(noTableOk=False, **_table_defaults())
    from yade.params import table
    fields = scan.KINDS[scan.kind_of(dict(kind=table.kind))].defaults
    case = scan.normalize_case(dict({k: getattr(table, k) for k in fields}, kind=table.kind))
    results = scan.ResultsFile(os.path.join(table.scanDir, 'results.jsonl'))
    # a resubmitted Slurm array runs every line of the whole scan again: finished cases end at once
    if scan.case_key(case) in results.done_keys():
        print('case %s is already in %s: skipped' % (scan.case_key(case), results.path))
        return
    if table.kind == 'drum':
        result = scan.run_drum_case(case, table.scanDir)
        results.append(result)
        print('%.3g revolutions: %d agglomerates, %d granules (%.3g of the mass), largest %d spheres; history in %s' % (
            case['revolutions'], result['agglomerates'], result['granules'], result['granulated_mass_fraction'],
            result['largest'], result['history']))
        return
    result = scan.find_critical_dt(case, os.path.join(table.scanDir, 'beds'))
    results.append(result)
    print('critical dt %.4g s (stable %.4g, unstable %.4g), stepper %.4g s' % (
        result['dt_critical'], result['dt_stable'], result['dt_unstable'], result['dt_stepper']))


if __name__ == '__main__':  # `yade -n -x job.py` runs the script in YADE's __main__
    main()
