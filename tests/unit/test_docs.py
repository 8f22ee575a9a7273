"""The physics reference ships with the product: every equation tag the code, the tests and the
documents cite (P…, R…, E…, physics.md §…) is defined in docs/physics.md."""
import glob
import os
import re

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
REFERENCE = os.path.join(TOP, 'docs', 'physics.md')
TAG = r'\b(?:P\d{1,2}[a-c]?|R[1-9]|E[1-9])\b'


def defined():
    with open(REFERENCE) as fh:
        text = fh.read()
    # a definition opens a paragraph or an item in bold: **P12.**, **P1, P2 (…)**, - **E1 (…)**
    heads = re.findall(r'^(?:- )?\*\*([^*]*)\*\*', text, re.M)
    tags = {t for h in heads for t in re.findall(TAG, h.split('(')[0])}
    sections = set(re.findall(r'^## (\d+)\.', text, re.M))
    return tags, sections


def sources():
    patterns = ['pkg/**/*.hpp', 'pkg/**/*.cpp', 'py/**/*.py', 'tests/**/*.py', 'tests/**/*.cpp', 'tests/**/*.hpp',
                'bench/*.py', 'examples/*.py', 'docs/*.md', 'README.md']
    for p in patterns:
        for path in glob.glob(os.path.join(TOP, p), recursive=True):
            if os.path.abspath(path) not in (REFERENCE, os.path.abspath(__file__)):
                yield path


def citations(path):
    """(line number, tag) of every tag cited in the file; '§N' where physics.md's section N is meant."""
    code = not path.endswith('.md')
    with open(path, errors='replace') as fh:
        for number, line in enumerate(fh, 1):
            for tag in re.findall(TAG, line):
                yield number, tag
            # in code, § always means physics.md; in the documents only when physics.md is named
            pattern = r'§(\d+)' if code else r'physics\.md[^§\n]{0,12}§(\d+)'
            for section in re.findall(pattern, line):
                yield number, '§' + section


def test_the_reference_defines_the_tags():
    tags, sections = defined()
    assert {'P3', 'P12', 'P14', 'P15', 'R1', 'E1'} <= tags
    assert {'1', '2', '3', '4', '5', '6'} <= sections


def test_every_citation_points_to_a_definition():
    tags, sections = defined()
    dangling = []
    for path in sources():
        for number, tag in citations(path):
            ok = tag[1:] in sections if tag.startswith('§') else tag in tags
            if not ok:
                dangling.append('%s:%d: %s' % (os.path.relpath(path, TOP), number, tag))
    assert not dangling, 'citations without a definition in docs/physics.md:\n' + '\n'.join(dangling)
