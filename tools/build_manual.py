"""Build the HTML manual (docs/) with Sphinx: ``python3 tools/build_manual.py [--source DOCS] [OUTDIR]``,
inside the project's environment (``./yadew docs`` runs it; so does tests/system/test_manual.py).
OUTDIR defaults to docs/_build/html; --source builds a copy of docs/ instead (the tests build a copy
with a page changed), which must sit beside a copy of pkg/viscbridge/plugin/Plugin.cpp as docs/ does.

The reference pages are generated from the live classes, so YADE with the plugin must be importable
in this process (the environment's PYTHONPATH and YADE_PREFIX do that).  Every warning is an error
(-W), and --keep-going lists all of them in one run; a fresh environment (-E) each time, so that
warnings of pages that did not change are reported again.  Exit status: Sphinx's (0: no warning).
"""
import argparse
import os
import sys
import tempfile

TOP = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(TOP, 'docs')
DEFAULT_OUT = os.path.join(DOCS, '_build', 'html')


def sphinx_arguments(source, out, doctrees):
    """sphinx-build's command line: warnings as errors, all of them listed, nothing reused."""
    return ['-W', '--keep-going', '-E', '-q', '-b', 'html', '-d', doctrees, source, out]


def check_environment():
    """Fail early, with what to do, where the reference could not be generated."""
    try:
        import sphinx  # noqa: F401
        import myst_parser  # noqa: F401
    except ImportError as e:
        sys.exit('build_manual: %s; run it through ./yadew docs (the environment has Sphinx and MyST)' % e)
    try:
        import yade.wrapper
    except ImportError as e:
        sys.exit('build_manual: cannot import yade (%s); the reference is generated from the live classes: '
                 'run it through ./yadew docs' % e)
    if not hasattr(yade.wrapper, 'ViscBridgeGuard'):
        sys.exit('build_manual: YADE was imported without the ViscBridge plugin (YADE_PREFIX=%s); '
                 'run it through ./yadew docs' % os.environ.get('YADE_PREFIX'))


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog='build_manual.py', description=__doc__.split('\n\n')[0])
    parser.add_argument('--source', default=DOCS, help='the docs directory to build (default: %(default)s)')
    parser.add_argument('out', nargs='?', default=DEFAULT_OUT, help='output directory (default: %(default)s)')
    return parser.parse_args(argv)


def main(argv):
    args = parse_arguments(argv)
    out, source = os.path.abspath(args.out), os.path.abspath(args.source)
    if not os.path.isfile(os.path.join(source, 'conf.py')):
        sys.exit('build_manual: %s has no conf.py: not a copy of docs/' % source)
    check_environment()
    from sphinx.cmd.build import build_main
    with tempfile.TemporaryDirectory(prefix='viscbridge-doctrees-') as doctrees:
        status = build_main(sphinx_arguments(source, out, doctrees))
    if status == 0:
        print('build_manual: %s' % os.path.join(out, 'index.html'))
    return status


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
