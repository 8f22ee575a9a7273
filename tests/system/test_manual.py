"""The HTML manual builds as `./yadew docs` builds it (tools/build_manual.py: Sphinx with every
warning an error) and holds what a reader looks for: every page of the index, the class reference
read off the plugin, the Python reference, :yref: links resolved, the equation anchors of physics.md.
A second build, of a copy of docs/ with a page changed, shows that a warning fails the build."""
import glob
import os
import re
import shutil
import subprocess
import sys

import pytest

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
DOCS = os.path.join(TOP, 'docs')
BUILD_MANUAL = os.path.join(TOP, 'tools', 'build_manual.py')


def build(out, *options):
    """Run tools/build_manual.py as ./yadew docs does; the completed process."""
    return subprocess.run([sys.executable, BUILD_MANUAL, *options, str(out)], capture_output=True,
                          text=True, timeout=600, env=dict(os.environ, OMP_NUM_THREADS='1'))


@pytest.fixture(scope='module')
def manual(tmp_path_factory):
    out = tmp_path_factory.mktemp('manual')
    proc = build(out)
    assert proc.returncode == 0, 'the manual does not build cleanly:\n%s\n%s' % (proc.stdout[-3000:], proc.stderr[-6000:])
    return out


def page(manual, name):
    with open(os.path.join(manual, name + '.html')) as fh:
        return fh.read()


def index_entries():
    """The documents the toctrees of docs/index.md list."""
    with open(os.path.join(DOCS, 'index.md')) as fh:
        blocks = re.findall(r'^```\{toctree\}\n(.*?)^```', fh.read(), re.S | re.M)
    return [line.strip() for block in blocks for line in block.splitlines()
            if line.strip() and not line.startswith(':')]


def test_every_page_of_the_index_and_of_docs_is_written(manual):
    entries = index_entries()
    assert {'timestep', 'reference/classes', 'reference/python', 'physics', 'performance'} <= set(entries)
    existing = [e for e in entries if glob.glob(os.path.join(DOCS, e + '.*'))]
    pages = ['index'] + existing + [os.path.relpath(p, DOCS)[:-3] for p in glob.glob(os.path.join(DOCS, '*.md'))]
    missing = [p for p in pages if not os.path.exists(os.path.join(manual, p + '.html'))]
    assert not missing, 'pages not written: %s' % missing
    index = page(manual, 'index')
    for entry in existing:
        assert 'href="%s.html"' % entry in index, '%s is not linked from the index' % entry


def test_the_class_reference_documents_every_plugin_class(manual):
    with open(os.path.join(TOP, 'pkg', 'viscbridge', 'plugin', 'Plugin.cpp')) as fh:
        registered = re.findall(r'\((\w+)\)', re.search(r'YADE_PLUGIN\((.*?)\);', fh.read(), re.S).group(1))
    html = page(manual, 'reference/classes')
    assert 'ViscBridgeSpray' in registered
    for name in registered:
        assert 'id="yade.wrapper.%s"' % name in html, name
    # an attribute with its docstring, type and default; a method; a static method
    entry = html[html.index('id="yade.wrapper.ViscBridgeSpray.maxFilmRel"'):]
    entry = entry[:entry.index('</dd>')]
    assert "The largest film the spray builds on a sphere" in entry
    assert re.search(r'<span class="pre">=</span>.*<span class="pre">0.1</span>', entry), entry  # maxFilmRel = 0.1
    assert re.search(r'Type <code[^>]*><span class="pre">Real</span></code>\.', entry), entry
    read_only = html[html.index('id="yade.wrapper.ViscBridgeSpray.delivered"'):]
    assert 'read-only' in read_only[:read_only.index('</dd>')]
    for anchor in ('ViscBridgeSpray.dropletVolume', 'ViscBridgeGuard.rebaseline', 'ViscBridgeState.of',
                   'ViscBridgeContext.warnOnce'):
        assert 'id="yade.wrapper.%s"' % anchor in html, anchor
    # YADE's classes link to YADE's reference
    assert 'href="https://yade-dem.org/doc/yade.wrapper.html#yade.wrapper.PeriodicEngine"' in html


def test_the_python_reference_documents_the_package(manual):
    html = page(manual, 'reference/python')
    for name in ('viscbridge.engines', 'viscbridge.liquid.spray', 'viscbridge.scenes.settling',
                 'viscbridge.criteria.critical_dt', 'viscbridge.scan.find_critical_dt', 'viscbridge.vtk.bridge_recorder',
                 'viscbridge.mpi.to_serial', 'viscbridge.analysis.agglomerate_history.AgglomerateHistory'):
        assert 'id="%s"' % name in html, name
    # a parameter paragraph of a docstring is a parameter of the list
    entry = html[html.index('id="viscbridge.engines"'):]
    assert re.search(r'<strong>integration</strong>', entry[:entry.index('</dl>')])
    # :yref: to our class goes to the class reference
    spray = html[html.index('id="viscbridge.liquid.spray"'):]
    assert 'href="classes.html#yade.wrapper.ViscBridgeSpray"' in spray[:spray.index('</dd>')]


def test_no_role_is_left_unrendered(manual):
    """A role shows as its text only where a page or a docstring writes it as code (contributing.md
    explains :yref:); anywhere else it was not parsed."""
    for path in glob.glob(os.path.join(manual, '**', '*.html'), recursive=True):
        with open(path) as fh:
            text = re.sub(r'<(code|pre)\b.*?</\1>', '', fh.read(), flags=re.S)
        for role in (':yref:', ':ydefault:', ':yattrtype:', '{yref}', ':func:', ':class:', ':mod:'):
            assert role not in text, '%s in %s' % (role, os.path.relpath(path, manual))


def test_physics_equation_labels_have_anchors(manual):
    html = page(manual, 'physics')
    for label in ('p14', 'p0a', 'p1', 'p2', 'a4a', 'e5', 'l6b', 'r3'):
        assert 'id="%s"' % label in html, label
    # the anchor is on the label's definition, not on its first mention in the introduction
    assert re.search(r'id="p14">P14</strong>', html)
    assert 'id="sec-7a"' in html


def test_the_reference_links_its_citations_of_physics(manual):
    classes = page(manual, 'reference/classes')
    guard = classes[classes.index('id="yade.wrapper.ViscBridgeGuard"'):]
    guard = guard[:guard.index('id="yade.wrapper.ViscBridgeGuard.iterPeriod"')]
    assert 'href="../physics.html#e5">E5</a>' in guard, guard[-2000:]
    assert 'href="../physics.html#p14">P14</a>' in guard
    python = page(manual, 'reference/python')
    assert 'href="../physics.html#l6b">L6b</a>' in python


@pytest.fixture(scope='module')
def changed_copy(tmp_path_factory):
    """A build of a copy of docs/ with two bad :yref: and a missing anchor added."""
    root = tmp_path_factory.mktemp('copy')
    shutil.copytree(DOCS, root / 'docs', ignore=shutil.ignore_patterns('_build', 'data'))
    plugin = root / 'pkg' / 'viscbridge' / 'plugin'
    plugin.mkdir(parents=True)
    shutil.copy(os.path.join(TOP, 'pkg', 'viscbridge', 'plugin', 'Plugin.cpp'), plugin)
    with open(root / 'docs' / 'liquid.md', 'a') as fh:
        fh.write('\nSee {yref}`ViscBridgeSpray.noSuchAttribute` and {yref}`NoSuchYadeClass`; '
                 '[P14](physics.md#p14), [§7](physics.md#sec-7) and [a label physics.md lacks](physics.md#p99).\n')
    out = root / 'html'
    return build(out, '--source', str(root / 'docs')), out


def test_a_warning_fails_the_build_and_every_warning_is_listed(changed_copy):
    proc, _ = changed_copy
    assert proc.returncode != 0
    assert 'yade.wrapper.ViscBridgeSpray.noSuchAttribute' in proc.stderr, proc.stderr[-3000:]
    assert re.search(r'NoSuchYadeClass.*YADE \S+ has no yade.wrapper.NoSuchYadeClass', proc.stderr), proc.stderr[-3000:]
    assert "local id not found in doc 'physics': 'p99'" in proc.stderr, proc.stderr[-3000:]


def test_a_page_links_to_an_equation_label_in_markdown(changed_copy):
    proc, out = changed_copy
    liquid = (out / 'liquid.html').read_text()
    assert 'href="physics.html#p14"' in liquid and 'href="physics.html#sec-7"' in liquid
    assert "'p14'" not in proc.stderr and "'sec-7'" not in proc.stderr
