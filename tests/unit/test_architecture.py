"""The layers of docs/architecture.md hold in the tree: what each folder of pkg/viscbridge may use,
engines that never know each other, and a document that names every file."""
import os
import re

import pytest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
PKG = os.path.join(ROOT, 'pkg', 'viscbridge')
ENGINES = ('ViscBridgeGuard', 'ViscBridgeTimeStepper', 'ViscBridgeImplicitSolver')
# what each layer may include of the plugin, in the order of docs/architecture.md (core/ includes no YADE)
MAY_USE = {
    'core': {'core'},
    'distributed': {'core', 'distributed'},
    'yade': {'core', 'distributed', 'yade'},
    'scene': {'core', 'distributed', 'yade', 'scene'},
    'engines': {'core', 'distributed', 'yade', 'scene', 'engines'},
    'plugin': {'core', 'distributed', 'yade', 'scene', 'engines', 'plugin'},
}


def sources():
    for folder, _dirs, files in os.walk(PKG):
        for f in sorted(files):
            if f.endswith(('.hpp', '.cpp')):
                path = os.path.join(folder, f)
                yield os.path.relpath(path, PKG), open(path).read()


def includes(text):
    return re.findall(r'#include\s+[<"]([^>"]+)[>"]', text)


def engine_of(path):
    name = os.path.basename(path)
    return next((e for e in ENGINES if path.startswith('engines/') and name.startswith(e)), None)


@pytest.mark.parametrize('path,text', list(sources()), ids=lambda x: x if isinstance(x, str) and '/' in x else '')
def test_each_file_uses_only_the_layers_below_it(path, text):
    layer = path.split('/')[0]
    assert layer in MAY_USE, 'a folder docs/architecture.md does not describe: %s' % layer
    for inc in includes(text):
        if inc.startswith('viscbridge/'):
            used = inc.split('/')[1]
            assert used in MAY_USE[layer], '%s (layer %s) includes %s' % (path, layer, inc)
        elif layer == 'core':
            assert not inc.startswith(('core/', 'pkg/', 'lib/')), '%s is YADE-free but includes %s' % (path, inc)


def test_no_engine_includes_or_casts_to_another_engine():
    for path, text in sources():
        if path.startswith('plugin/'):
            continue  # the registration of every class
        own = engine_of(path)
        for other in ENGINES:
            if other == own:
                continue
            for inc in includes(text):
                assert not re.search(r'engines/%s\w*\.hpp$' % other, inc), '%s includes %s' % (path, inc)
            assert not re.search(r'_cast\s*<\s*(const\s+)?%s\b' % other, text), '%s casts to %s' % (path, other)


def test_the_architecture_document_names_every_file_and_folder():
    doc = open(os.path.join(ROOT, 'docs', 'architecture.md')).read()
    missing = [p for p, _ in sources() if os.path.splitext(os.path.basename(p))[0] not in doc]
    assert not missing, 'docs/architecture.md does not name: %s' % ', '.join(missing)
    for folder, _dirs, _files in os.walk(PKG):
        rel = os.path.relpath(folder, PKG)
        if rel != '.':
            assert rel + '/' in doc, 'docs/architecture.md does not describe the folder %s/' % rel
    py = os.path.join(ROOT, 'py', 'viscbridge')
    for entry in sorted(os.listdir(py)):
        name = entry[:-3] if entry.endswith('.py') else entry
        if entry.startswith('__') or not (entry.endswith('.py') or os.path.isdir(os.path.join(py, entry))):
            continue
        assert name in doc, 'docs/architecture.md does not name py/viscbridge/%s' % entry
