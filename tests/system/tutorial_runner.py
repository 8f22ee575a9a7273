"""Running a tutorial of docs/ as a reader runs it: its blocks in order, in one working directory —
the Python blocks in one `yade -n -x` process, each shell block at its place (`./yadew sh CMD` is CMD
here: the tests run inside the environment).  Used by tests/system/test_tutorial_*.py, one file per
tutorial so that ctest runs them side by side."""
import os
import re

import pytest

from yadeproc import run_yade

DOCS = os.path.join(os.path.dirname(__file__), '..', '..', 'docs')

SHELL = '''
import subprocess as _subprocess
def _sh(line):
    done = _subprocess.run(['bash', '-c', line], capture_output=True, text=True)
    print(done.stdout)
    if done.returncode:
        raise SystemExit('%s exited with %d:\\n%s' % (line, done.returncode, done.stderr[-3000:]))
'''


def script(name):
    """The tutorial as one script: Python blocks as they are, shell lines as _sh(...) calls."""
    with open(os.path.join(DOCS, name)) as fh:
        blocks = re.findall(r'^```(python|sh)\n(.*?)^```', fh.read(), re.S | re.M)
    parts = [SHELL]
    for language, text in blocks:
        if language == 'python':
            parts.append(text)
        else:
            for line in text.replace('\\\n', ' ').splitlines():
                if line.strip():
                    parts.append('_sh(%r)' % line.replace('./yadew sh ', '', 1))
    return '\n'.join(parts)


def run_tutorial(name, work):
    """Run docs/`name` in the directory `work`; returns what it printed."""
    (work / 'tutorial.py').write_text(script(name))
    proc, _ = run_yade(str(work / 'tutorial.py'), timeout=1800, cwd=str(work))
    return proc.stdout


def tutorial_fixture(name):
    """A module fixture that runs docs/`name` once and gives (working directory, what it printed)."""
    @pytest.fixture(scope='module')
    def run(tmp_path_factory):
        work = tmp_path_factory.mktemp(name.split('.')[0])
        return work, run_tutorial(name, work)
    return run
