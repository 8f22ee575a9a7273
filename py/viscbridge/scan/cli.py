"""The command line of a scan (``python3 -m viscbridge.scan COMMAND DIR ...``): its parser, with the
case fields of every kind in ``--help``, the commands run, table, collect and slurm (run and table
take ``--kind settling`` or ``--kind drum``), and exit codes (0; 1 with a one-line error; 130 when
interrupted).  Plain Python (the cases run in yade-batch's processes).
"""
import argparse
import json
import os
import sys

from .batch import interruptible, run_cases
from .cases import KINDS, _allowed, grid, one_at_a_time
from .errors import ScanError
from .results import collect
from .slurm import slurm_script
from .table import write_table

__all__ = ['build_parser', 'main', 'fields_help']


def _parse_value(text):
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def _parse_assignments(items, lists):
    out = {}
    for item in items or []:
        if '=' not in item:
            raise ValueError('expected FIELD=VALUE%s, got %r' % (',VALUE...' if lists else '', item))
        k, v = item.split('=', 1)
        out[k] = [_parse_value(x) for x in v.split(',')] if lists else _parse_value(v)
    return out


def _cases_from_args(args):
    base = _parse_assignments(args.base, lists=False)
    kind = getattr(args, 'kind', None)
    if kind is not None:
        if base.get('kind', kind) != kind:
            raise ValueError('--kind %s and --base kind=%s disagree; allowed: one kind' % (kind, base['kind']))
        base['kind'] = kind
    variations = _parse_assignments(args.vary, lists=True)
    if args.grid:
        return grid(base, **variations)
    return one_at_a_time(base, **variations)


def fields_help(kinds=tuple(KINDS)):
    """The list of case fields of --help, for each of `kinds`: name, default, unit, meaning and
    allowed values."""
    blocks = []
    for kind in kinds:
        spec = KINDS[kind]
        lines = ['%s case fields (--kind %s: %s; FIELD=VALUE, the unit is SI, "-" for none):' % (kind, kind, spec.meaning),
                 '  %-16s %-14s %-6s %s' % ('FIELD', 'DEFAULT', 'UNIT', 'MEANING; ALLOWED')]
        for name, default in spec.defaults.items():
            shown = '%g' % default if isinstance(default, float) else str(default)
            field = spec.fields[name]
            lines.append('  %-16s %-14s %-6s %s; %s' % (name, shown, field.unit or '-', field.meaning, _allowed(name, kind)))
        blocks.append('\n'.join(lines))
    return '\n\n'.join(blocks)


_COMMANDS = dict(
    run="run the scan's cases not yet in DIR/results.jsonl through yade-batch",
    table='only write DIR/cases.table, the yade-batch table of the scan',
    collect='write DIR/results.csv from DIR/results.jsonl (the latest result per case)',
    slurm='write DIR/scan.sbatch, a Slurm array job over the whole scan (DIR/cases.table); '
          'its tasks skip finished cases, so it can be resubmitted as it is',
)


def build_parser():
    """The command line's parser; every command and option has a help text, and the help of the
    parser and of `run` and `table` lists the case fields."""
    fmt = dict(formatter_class=argparse.RawDescriptionHelpFormatter, epilog=fields_help())
    description = sys.modules[__package__].__doc__.split('\n\n')[0]  # the package's first paragraph
    p = argparse.ArgumentParser(prog='python3 -m viscbridge.scan', description=description, **fmt)
    sub = p.add_subparsers(dest='command', required=True, metavar='COMMAND')
    for name, text in _COMMANDS.items():
        s = sub.add_parser(name, help=text, description=text, **(fmt if name in ('run', 'table') else {}))
        s.add_argument('dir', metavar='DIR', help='scan directory' + (' (created if missing)' if name in ('run', 'table') else ''))
        if name in ('run', 'table'):
            _add_case_options(s)
        if name == 'run':
            s.add_argument('-j', '--jobs', type=int, default=os.cpu_count() or 1,
                           help='cases run at the same time (default: the number of CPUs, %(default)s)')
    return p


def _add_case_options(parser):
    parser.add_argument('--kind', choices=tuple(KINDS), default=None,
                        help="the kind of the scan's cases (default: settling): %s" % '; '.join(
                            '%s, %s' % (k, spec.meaning) for k, spec in KINDS.items()))
    parser.add_argument('--base', nargs='*', action='extend', metavar='FIELD=VALUE',
                        help='fields of the base case (the others at their defaults)')
    parser.add_argument('--vary', nargs='*', action='extend', metavar='FIELD=V1,V2',
                        help='values of a field, varied one field at a time from the base case (all combinations with --grid)')
    parser.add_argument('--grid', action='store_true', help='run every combination of the --vary values')


def _run(args):
    cases = _cases_from_args(args)  # every case is checked before anything is written
    try:
        rows = run_cases(cases, args.dir, jobs=args.jobs)
    finally:
        if os.path.isdir(args.dir):  # what finished is in results.csv too, whatever happened after
            collect(args.dir)
    print('scan: %d results in %s' % (len(rows), os.path.join(os.path.abspath(args.dir), 'results.csv')))


def _table(args):
    cases = _cases_from_args(args)
    os.makedirs(args.dir, exist_ok=True)
    print(write_table(cases, os.path.join(args.dir, 'cases.table'), args.dir))


def _collect(args):
    rows = collect(args.dir)
    if not rows:
        raise ScanError('no finished case in %s' % os.path.join(args.dir, 'results.jsonl'))
    print('%d results -> %s' % (len(rows), os.path.join(args.dir, 'results.csv')))


def _slurm(args):
    print(slurm_script(args.dir))


def main(argv=None):
    """The command line; returns the exit status.  Errors are reported on stderr without a traceback."""
    args = build_parser().parse_args(argv)
    try:
        with interruptible():
            dict(run=_run, table=_table, collect=_collect, slurm=_slurm)[args.command](args)
    except KeyboardInterrupt:
        resume = ('; yade-batch stopped, finished cases kept in %s; run the same command again to resume'
                  % os.path.join(os.path.abspath(args.dir), 'results.jsonl')) if args.command == 'run' else ''
        print('scan: interrupted%s' % resume, file=sys.stderr)
        return 130
    except (ValueError, ScanError, OSError) as e:
        print('scan: error: %s' % e, file=sys.stderr)
        return 1
    return 0
