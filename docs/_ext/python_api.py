"""The Python reference, generated from the package: the ``viscbridge-modules`` directive.

Every public module of ``viscbridge`` (no name part starting with '_') that declares ``__all__``
gets a section: its docstring, then each name of its ``__all__`` by autodoc (signature and
docstring; a class with its documented members; a constant with its value when that is short).  A
name that several modules export (``viscbridge.criteria`` re-exports ``viscbridge.planning``, the
packages their modules) is documented once, under the first module that exports it, and the others
link to it.  The directive's content gives the order of the first modules; every other public
module follows, in alphabetical order, so a new module appears by itself.

How the docstrings are read (parameter lines, constants' comments, names relative to their module):
python_docstrings.py; YADE's markup in them (:yref:, $formula$): yade_markup.py.
"""
import ast
import importlib
import importlib.util
import inspect
import pkgutil

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

from yade_markup import report_block_quotes

PACKAGE = 'viscbridge'
SHORT_VALUE = 60  # a constant's value is shown when its repr is at most this long
# id(object) -> the full name it is documented under, for the page being built (reference_rst)
DOCUMENTED = {}


def declares_all(path):
    """Whether the source file at `path` assigns __all__ (read, not imported: a script such as
    viscbridge/scan_job.py runs when imported)."""
    with open(path) as fh:
        tree = ast.parse(fh.read(), path)
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, 'id', None) == '__all__' for t in node.targets):
            return True
        if isinstance(node, ast.ImportFrom) and any(a.name == '__all__' for a in node.names):
            return True  # viscbridge.criteria: `from .planning import __all__`
    return False


def public_modules():
    """Names of the package's public modules that declare __all__, alphabetically."""
    package = importlib.import_module(PACKAGE)
    found = [PACKAGE] if declares_all(package.__file__) else []
    for info in pkgutil.walk_packages(package.__path__, PACKAGE + '.'):
        if any(part.startswith('_') for part in info.name.split('.')):
            continue
        if declares_all(importlib.util.find_spec(info.name).origin):
            found.append(info.name)
    return sorted(found)


def module_order(first):
    """`first` (checked to be public modules with __all__), then the other public modules."""
    available = public_modules()
    unknown = [m for m in first if m not in available]
    if unknown:
        raise ValueError('viscbridge-modules lists %s, which %s no public module of viscbridge with __all__'
                         % (', '.join(unknown), 'is' if len(unknown) == 1 else 'are'))
    return list(first) + [m for m in available if m not in first]


def directive_for(obj):
    if inspect.isclass(obj):
        return 'autoclass'
    if callable(obj):
        return 'autofunction'
    return 'autodata'


def entry_rst(full_name, obj):
    lines = ['.. %s:: %s' % (directive_for(obj), full_name)]
    if directive_for(obj) == 'autoclass':
        lines.append('   :members:')
    elif directive_for(obj) == 'autodata' and len(repr(obj)) > SHORT_VALUE:
        lines.append('   :no-value:')
    return lines + ['']


def reference_rst(first):
    """(the reference as reStructuredText: a section per module, each name once;
    [(alias, documented name)] of the names documented under another module)."""
    documented = {}  # (id(object), name) -> the full name it is documented under
    aliases = []
    lines = []
    for module_name in module_order(first):
        module = importlib.import_module(module_name)
        lines += [module_name, '-' * len(module_name), '', '.. automodule:: %s' % module_name, '   :no-members:']
        # viscbridge.scenes.drum is a module and, as scenes' function drum, an object: indexed once
        if module_name in documented.values():
            lines.append('   :no-index:')
        lines.append('')
        elsewhere = []
        for name in module.__all__:
            obj = getattr(module, name)
            key = (id(obj), name)
            if key in documented:
                elsewhere.append(':py:obj:`%s <%s>`' % (name, documented[key]))
                aliases.append(('%s.%s' % (module_name, name), documented[key]))
                continue
            documented[key] = "%s.%s" % (module_name, name)
            if callable(obj):  # (a value may be shared: 0, True, a short string)
                DOCUMENTED[id(obj)] = documented[key]
            lines += entry_rst(documented[key], obj)
        if elsewhere:
            lines += ['Also exported here, documented above: %s.' % ', '.join(elsewhere), '']
    return lines, aliases


def note_aliases(env, aliases):
    """Let references to a re-exported name (viscbridge.measures.instability, documented as
    viscbridge.scenes.instability) resolve to where it is documented."""
    domain = env.get_domain('py')
    for alias, documented in aliases:
        entry = domain.objects.get(documented)
        if entry is not None and alias not in domain.objects:
            domain.note_object(alias, entry.objtype, entry.node_id, aliased=True)


class ViscbridgeModules(SphinxDirective):
    """``.. viscbridge-modules::`` with the first modules, one a line, as content."""

    has_content = True

    def run(self):
        first = [line.strip() for line in self.content if line.strip()]
        try:
            text, aliases = reference_rst(first)
        except ValueError as e:
            raise self.error(str(e))
        parsed = nodes.Element()
        nested_parse_with_titles(self.state, StringList(text, 'viscbridge'), parsed)
        note_aliases(self.env, aliases)
        report_block_quotes(parsed)
        return parsed.children


def setup(app):
    app.add_directive('viscbridge-modules', ViscbridgeModules)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
