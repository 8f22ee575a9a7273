"""The command line of the analyses (``python3 -m viscbridge.analysis COMMAND ...``), in plain Python
(numpy and matplotlib, no YADE): ``compare`` overlays the agglomerate histories of several runs
(:func:`viscbridge.analysis.compare`).  Exit status: 0; 1 with a one-line error; 2 for a command line
that argparse refuses.
"""
import argparse
import sys

from .comparison import X_AXES, compare

__all__ = ['build_parser', 'main']


def build_parser():
    """The parser: one sub-command per analysis, every option with a help text."""
    p = argparse.ArgumentParser(prog='python3 -m viscbridge.analysis',
                                description='Analyses of ViscBridge runs, read back from their files (no YADE needed).')
    sub = p.add_subparsers(dest='command', required=True, metavar='COMMAND')
    text = 'overlay the agglomerate histories of several runs in one figure'
    c = sub.add_parser('compare', help=text, description=text + ' (viscbridge.analysis.compare): granules and '
                       'agglomerates, granulated mass fraction, granule d50 and the largest agglomerate, coordination '
                       'and the CoV of the liquid per particle, against revolutions or time, one colour per run, '
                       'labelled by the run parameters that differ between the runs.')
    c.add_argument('runs', nargs='+', metavar='RUN', help='a directory holding agglomerates.csv (and its sidecar '
                                                          'agglomerates.json), or such a CSV file')
    c.add_argument('-o', '--output', required=True, metavar='PATH', help='the figure to write (.png, .pdf or .svg)')
    c.add_argument('-x', '--x', default='revolutions', metavar='X',
                   help='the horizontal axis: %s (default: %%(default)s)' % ' or '.join(repr(k) for k in X_AXES))
    c.add_argument('--labels', nargs='+', metavar='LABEL', help='one legend label per run (default: the parameters '
                                                                 'that differ between the runs, else the directory names)')
    c.add_argument('--title', default='', help='a title over the figure')
    return p


def main(argv=None):
    """The command line; returns the exit status.  Errors are one line on stderr, without a traceback."""
    args = build_parser().parse_args(argv)
    try:
        print(compare(args.runs, args.output, x=args.x, labels=args.labels, title=args.title))
    except (ValueError, OSError) as e:
        print('analysis: error: %s' % e, file=sys.stderr)
        return 1
    return 0
