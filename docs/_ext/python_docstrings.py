"""How the Python reference reads our docstrings (autodoc-process-docstring), so that they are
written for ``help()`` and still render as a reference:

- a constant's documentation comment (``#:`` before it, or a string after it) is found in the module
  that assigns it, also when the reference documents it under a package that re-exports it;
- parameter paragraphs — a line "name: meaning" at the docstring's margin, with its indented
  continuation, where name is a parameter of the signature — become the list of parameters;
- a role's relative name (:func:`compare`) means the name in the module that defines the object,
  also when the object is documented under another module;
- $formula$ is math (yade_markup.py);
- a public name without documentation is reported (a warning, so an error of the build).
"""
import importlib
import inspect
import re
import sys

from sphinx.pycode import ModuleAnalyzer
from sphinx.util import logging

from python_api import DOCUMENTED, public_modules
from yade_markup import docstring_to_rst

logger = logging.getLogger(__name__)

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
    app.setup_extension('python_api')
    app.connect('autodoc-process-docstring', process_docstring)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
