"""The Python reference, generated from the package: the ``viscbridge-modules`` directive.

Every public module of ``viscbridge`` (no name part starting with '_') that declares ``__all__``
gets a section: its docstring, then each name of its ``__all__`` by autodoc (signature and
docstring; a class with its documented members; a constant with its value when that is short).  A
name that several modules export (``viscbridge.criteria`` re-exports ``viscbridge.planning``, the
packages their modules) is documented once, under the first module that exports it, and the others
link to it.  The directive's content gives the order of the first modules; every other public
module follows, in alphabetical order, so a new module appears by itself.

Docstrings are written as reStructuredText with YADE's markup (:yref:, $formula$): see
yade_markup.py.
"""
import ast
import importlib
import importlib.util
import inspect
import pkgutil
import re
import sys

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.pycode import ModuleAnalyzer
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

from yade_markup import docstring_to_rst, report_block_quotes

logger = logging.getLogger(__name__)

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


# "name: text" opening a line, as our docstrings describe parameters
PARAMETER_LINE = re.compile(r'^(\w+): (.*)$')
# a Python role's target without an explicit title: :func:`name`, :data:`cases.DRUM_DEFAULTS`
RELATIVE_ROLE = re.compile(r':(func|class|data|obj|meth|attr|exc|mod):`([A-Za-z][\w.]*)`')


def parameter_fields(lines, parameters):
    """Our docstrings' parameter paragraphs ("integration: 'explicit', ..." and its indented
    continuation, at the docstring's left margin) as reStructuredText fields (":param integration:
    ..."), which the manual shows as a list of parameters; other lines unchanged."""
    out, in_fields = [], False
    for line in lines:
        m = PARAMETER_LINE.match(line)
        if m and m.group(1) in parameters:
            if out and out[-1].strip() and not in_fields:
                out.append('')
            out.append(':param %s: %s' % m.groups())
            in_fields = True
            continue
        if in_fields and line.strip() and not line[0].isspace():
            out.append('')  # a field list ends with a blank line
        if not line.strip() or not line[0].isspace():
            in_fields = False
        out.append(line)
    return out


def parameters_of(obj):
    try:
        return set(inspect.signature(obj).parameters)
    except (TypeError, ValueError):
        return set()


def defining_module(what, obj):
    """The module a docstring's relative names (:func:`compare`) refer to: where `obj` is defined."""
    if what in ('function', 'class', 'method', 'exception'):
        return getattr(obj, '__module__', None)
    return None


def documented_module(name):
    """The module a documented name is in, which Sphinx resolves its docstring's names against:
    viscbridge.scenes for viscbridge.scenes.Settling.run."""
    parts = name.split('.')
    for n in range(len(parts) - 1, 0, -1):
        if '.'.join(parts[:n]) in sys.modules:
            return '.'.join(parts[:n])
    return None


def lookup(module_name, dotted):
    obj = sys.modules.get(module_name)
    for part in dotted.split('.'):
        obj = getattr(obj, part, None)
        if obj is None:
            return None
    return obj


def absolute_roles(text, module_name, context_name):
    """:func:`name` written in module `module_name` as :func:`name <documented.name>` where Sphinx
    would look it up in another module, `context_name` (where the object is documented): the name as
    the docstring's module sees it, where the reference documents it.  viscbridge.scan.run_drum_case
    is defined in viscbridge.scan.drum_trial, whose names its docstring uses; :func:`instability` in
    viscbridge.scenes.runner is the one of viscbridge.measures.  Names it cannot find are left to
    Sphinx, which reports those it cannot resolve either."""
    def absolute(m):
        role, target = m.groups()
        obj = lookup(module_name, target)
        if obj is None or role == 'mod' or lookup(context_name, target) is obj:
            return m.group(0)
        return ':%s:`%s <%s>`' % (role, target, DOCUMENTED.get(id(obj)) or '%s.%s' % (module_name, target))
    return RELATIVE_ROLE.sub(absolute, text)


def data_docstring(name, obj):
    """The documentation comment (#: or a string after it) of a constant, from the public module
    that assigns it: autodoc reads only the module it is documented under, and would otherwise show
    the docstring of the value's type (dict's)."""
    short = name.rsplit('.', 1)[-1]
    for module_name in public_modules():
        module = sys.modules.get(module_name) or importlib.import_module(module_name)
        if getattr(module, short, None) is not obj:
            continue
        docs = ModuleAnalyzer.for_module(module_name).find_attr_docs()
        if ('', short) in docs:
            return list(docs[('', short)])
    return []


def process_docstring(app, what, name, obj, options, lines):
    """Our docstrings as the manual shows them: a constant's documentation comment, parameter
    paragraphs as fields, relative names of the defining module made absolute, $formula$ as math.
    A public name without any documentation is reported (a warning: an error in the build)."""
    if what == 'data':
        lines[:] = data_docstring(name, obj)
    text = '\n'.join(parameter_fields(lines, parameters_of(obj)) if callable(obj) else lines)
    module_name, context_name = defining_module(what, obj), documented_module(name)
    if module_name and context_name and module_name != context_name:
        text = absolute_roles(text, module_name, context_name)
    lines[:] = docstring_to_rst(text).split('\n')
    if what in ('module', 'function', 'class', 'data', 'exception') and not ''.join(lines).strip():
        logger.warning('%s %s has no docstring: say what it is and why (the reference shows it)',
                       what, name, type='viscbridge', subtype='undocumented')


def setup(app):
    app.add_directive('viscbridge-modules', ViscbridgeModules)
    app.connect('autodoc-process-docstring', process_docstring)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
