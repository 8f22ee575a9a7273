"""Every shell command the README and the manual show names something that exists: a `./yadew`
command, a script of the repository, a `python3 -m viscbridge.X SUBCOMMAND` that accepts its
options.  (The tutorials' commands run in full: tests/system/test_tutorial_*.py; the benchmarks'
run for minutes to hours and are not run here.)"""
import glob
import os
import re
import shlex
import subprocess
import sys

import pytest

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
DOCUMENTS = [os.path.join(TOP, 'README.md')] + sorted(glob.glob(os.path.join(TOP, 'docs', '**', '*.md'), recursive=True))
OTHER_TOOLS = ('sbatch', 'mpiexec')  # a cluster's, not ours
USERS_OWN = ('my_scene.py',)  # a script the reader writes


def commands():
    """(document, command line as words) for every line of every shell block."""
    found = []
    for path in DOCUMENTS:
        if '_build' in path:
            continue
        text = open(path).read()
        for block in re.findall(r'^```(?:sh|bash|shell)\n(.*?)^```', text, re.S | re.M):
            for line in block.replace('\\\n', ' ').splitlines():
                words = shlex.split(line, comments=True)
                if words:
                    found.append((os.path.relpath(path, TOP), words))
    return found


def yadew_commands():
    usage = subprocess.run([os.path.join(TOP, 'yadew'), 'help'], capture_output=True, text=True).stdout
    return set(re.findall(r'^  (\w+)', usage, re.M))


CASES = commands()


def test_the_documents_show_commands():
    assert len(CASES) > 20


@pytest.mark.parametrize('document, words', CASES, ids=['%s: %s' % (d, ' '.join(w)[:60]) for d, w in CASES])
def test_a_shown_command_names_what_exists(document, words):
    if words[0] in OTHER_TOOLS:
        return
    if words[0] == './yadew':
        assert words[1] in yadew_commands(), '%s: ./yadew has no command %r' % (document, words[1])
        words = words[2:]
        if not words or words[0] == 'sh':
            words = words[1:]
    scripts = [w for w in words if w.endswith('.py') and w not in USERS_OWN]
    for script in scripts:
        assert os.path.isfile(os.path.join(TOP, script)), '%s: no script %s' % (document, script)
    if words[:2] == ['python3', '-m'] and words[2].startswith('viscbridge'):
        # the module and its subcommand exist and accept the options shown ('[...]' marks optional ones)
        shown = [w for w in words[3:] if not w.startswith('[') and not w.endswith(']')]
        subcommand = [w for w in shown if not w.startswith('-')][:1]
        options = [w for w in shown if w.startswith('-')]
        probe = [sys.executable, '-m', words[2]] + subcommand + ['--help']
        done = subprocess.run(probe, capture_output=True, text=True, cwd=TOP, env=dict(os.environ, PYTHONPATH=os.path.join(TOP, 'py')))
        assert done.returncode == 0, '%s: %s\n%s' % (document, ' '.join(probe), done.stderr[-1500:])
        for option in options:
            assert option.split('=')[0] in done.stdout, '%s: %s does not take %s' % (document, ' '.join(words[2:4]), option)
