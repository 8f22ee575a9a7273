"""Every Python snippet in README.md and the Markdown pages of docs/ (subfolders included, not the
built manual) runs as shown: the blocks of one document run in order in one `yade -n -x` process, as
a reader pasting them into a YADE session would."""
import glob
import os
import re

import pytest

from yadeproc import run_yade

TOP = os.path.join(os.path.dirname(__file__), '..', '..')
# the tutorials run in test_tutorial_*.py, shell blocks too, with their numbers checked
RUN_ELSEWHERE = ('tutorial_granulation.md', 'tutorial_settling.md')
PAGES = [p for p in glob.glob(os.path.join(TOP, 'docs', '**', '*.md'), recursive=True)
         if '_build' not in os.path.relpath(p, TOP).split(os.sep)]
DOCUMENTS = [os.path.join(TOP, 'README.md')] + sorted(d for d in PAGES if os.path.basename(d) not in RUN_ELSEWHERE)


def python_blocks(path):
    with open(path) as fh:
        return re.findall(r'^```python\n(.*?)^```', fh.read(), re.S | re.M)


WITH_SNIPPETS = [d for d in DOCUMENTS if python_blocks(d)]


def test_the_readme_has_its_snippet():
    assert python_blocks(os.path.join(TOP, 'README.md'))


@pytest.mark.parametrize('document', WITH_SNIPPETS, ids=os.path.basename)
def test_snippets_run(document, tmp_path):
    script = tmp_path / 'snippets.py'
    script.write_text('\n'.join(python_blocks(document)))
    run_yade(str(script), timeout=600)


def test_readme_snippet_prints_a_checkable_result(tmp_path):
    """The README's example: a sphere pressed into the floor comes to sink at the speed at which the
    bridge's viscous force carries its weight."""
    script = tmp_path / 'readme.py'
    script.write_text(python_blocks(os.path.join(TOP, 'README.md'))[0])
    proc, _ = run_yade(str(script), timeout=600)
    m = re.search(r'viscous force ([0-9.e+-]+) N, weight ([0-9.e+-]+) N', proc.stdout)
    assert m, proc.stdout
    assert float(m.group(1)) == pytest.approx(float(m.group(2)), rel=2e-3)
