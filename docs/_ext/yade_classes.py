"""The class reference, generated from the running plugin: the ``{yade-classes}`` directive.

The classes are those pkg/viscbridge/plugin/Plugin.cpp registers (its YADE_PLUGIN list, read at
build time, so a class added there appears by itself); their docstrings, attributes and methods come
from ``yade.wrapper`` as the built plugin exposes them — what ``help()`` shows in a YADE session.
For each class: its YADE base classes (linked to YADE's reference), its docstring, every attribute
it adds (name = default, docstring, type, whether read-only or not saved), its Python methods with their
signatures, and the attributes it inherits from YADE's classes, by name.  The classes are grouped by
the YADE class they derive from (engines, functors, ...).
"""
import functools
import os
import re

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

from yade_markup import docstring_to_rst, report_block_quotes

TOP = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PLUGIN_SOURCE = os.path.join(TOP, 'pkg', 'viscbridge', 'plugin', 'Plugin.cpp')

# (section title, YADE base class) in the order the page shows them; the first that a class derives
# from is its group
GROUPS = [
    ('Engines', 'Engine'),
    ('Interaction functors', 'Functor'),
    ('Interaction physics', 'IPhys'),
    ('Particle state', 'State'),
    ('Scene attachments and diagnostics', 'Serializable'),
]
# YADE's attribute flags (lib/serialization/Serializable.hpp, Attr::...)
NO_SAVE, READ_ONLY = 1, 2
YADE_MARKUP = re.compile(r':(ydefault|yattrtype|yattrflags):`(.*?)`', re.S)
# Boost.Python's docstring of a function: "\nname( (Type)arg1, (str)key) -> ret :\n    doc"
BOOST_SIGNATURE = re.compile(r'^\s*(\w+)\((.*?)\)\s*->\s*(\S+)\s*:\s*\n', re.S)


@functools.lru_cache(maxsize=None)
def plugin_class_names():
    """The classes Plugin.cpp registers, in its order: YADE_PLUGIN((A)(B)...)."""
    with open(PLUGIN_SOURCE) as fh:
        source = re.sub(r'//[^\n]*', '', fh.read())
    m = re.search(r'YADE_PLUGIN\s*\(\s*\((.*?)\)\s*\)\s*;', source, re.S)
    if not m:
        raise RuntimeError('%s: no YADE_PLUGIN((...)) list found; the class reference is read from it'
                           % PLUGIN_SOURCE)
    return tuple(re.findall(r'(\w+)', m.group(1)))


def yade_markup(doc):
    """(text, {'ydefault': ..., 'yattrtype': ..., 'yattrflags': ...}) of an attribute's docstring."""
    fields = {k: v for k, v in YADE_MARKUP.findall(doc or '')}
    return YADE_MARKUP.sub('', doc or '').strip(), fields


def indent(text, prefix='   '):
    return [prefix + line if line.strip() else '' for line in text.splitlines()]


def yade_bases(cls):
    """YADE's classes above `cls`, nearest first, up to Serializable."""
    return [b for b in cls.__mro__[1:] if b.__module__ == 'yade.wrapper']


def attributes(cls):
    """(name, property) of the attributes `cls` adds, in the order the class declares them."""
    return [(k, v) for k, v in cls.__dict__.items() if isinstance(v, property) and not k.startswith('_')]


def methods(cls):
    """(name, function, is static) of the Python methods `cls` adds (not the Python wrappers of
    the special methods that viscbridge installs)."""
    found = []
    for name, raw in cls.__dict__.items():
        if name.startswith('_') or isinstance(raw, property):
            continue
        function = getattr(cls, name)
        if callable(function):
            found.append((name, function, isinstance(raw, staticmethod)))
    return found


def live_default(cls, name, fields):
    """The default as Python shows it on a new instance, else as the C++ declaration writes it."""
    try:
        value = getattr(cls(), name)
        return repr(0.0 if value == 0.0 and isinstance(value, float) else value)  # not -0.0
    except Exception:  # a class without a default constructor, an attribute that needs a scene
        return fields.get('ydefault', '')


def attribute_rst(cls, name, prop):
    text, fields = yade_markup(prop.__doc__)
    flags = int(fields.get('yattrflags') or 0)
    notes = ['Type ``%s``' % fields['yattrtype']] if fields.get('yattrtype') else []
    default = live_default(cls, name, fields)
    if flags & READ_ONLY:
        notes.append('read-only')
    if flags & NO_SAVE:
        notes.append('not saved with the scene')
    # the default shows in the signature line, as YADE's reference shows it: maxFilmRel = 0.1
    lines = ['.. py:attribute:: %s' % name] + (['   :value: %s' % default] if default else []) + ['']
    lines += indent(docstring_to_rst(text) or 'No description.')
    if notes:
        lines += ['', '   .. container:: yade-attribute-traits', '', '      %s.' % '; '.join(notes)]
    return lines + ['']


def boost_signature(function, static):
    """(signature, docstring) of a Boost.Python function: 'of(body: Body) -> ViscBridgeState'."""
    doc = function.__doc__ or ''
    m = BOOST_SIGNATURE.match(doc)
    if not m:
        return '%s()' % function.__name__, doc
    name, args, returned = m.groups()
    params = re.findall(r'\((\w+)\)\s*(\w+)', args)
    if not static:
        params = params[1:]  # self
    signature = '%s(%s) -> %s' % (name, ', '.join('%s: %s' % (a, t) for t, a in params), returned)
    body = doc[m.end():]
    body = re.split(r'\n\s*C\+\+ signature\s*:', body)[0]  # Boost's C++ signature, if shown
    return signature, '\n'.join(line.strip() for line in body.strip().splitlines())


def method_rst(name, function, static):
    signature, doc = boost_signature(function, static)
    lines = ['.. py:%s:: %s' % ('staticmethod' if static else 'method', signature), '']
    return lines + indent(docstring_to_rst(doc) or 'No description.') + ['']


def inherited_rst(cls):
    """One line per YADE base class: the attributes `cls` inherits from it, linked to YADE's reference."""
    lines = []
    for base in yade_bases(cls):
        names = [n for n, _ in attributes(base)]
        if names:
            links = ', '.join(':yref:`%s<%s.%s>`' % (n, base.__name__, n) for n in names)
            lines.append('   - from :yref:`%s`: %s' % (base.__name__, links))
    if not lines:
        return []
    return ['   .. rubric:: Inherited attributes', ''] + lines + ['']


def class_rst(cls):
    bases = yade_bases(cls)
    lines = ['.. py:class:: %s' % cls.__name__, '']
    if bases:
        lines += ['   Derives from %s.' % ' → '.join(':yref:`%s`' % b.__name__ for b in bases), '']
    lines += indent(docstring_to_rst(cls.__doc__ or 'No description.')) + ['']
    for name, prop in attributes(cls):
        lines += indent('\n'.join(attribute_rst(cls, name, prop)))
        lines.append('')
    for name, function, static in methods(cls):
        lines += indent('\n'.join(method_rst(name, function, static)))
        lines.append('')
    return lines + inherited_rst(cls)


def group_of(cls):
    names = {b.__name__ for b in cls.__mro__}
    for title, base in GROUPS:
        if base in names:
            return title
    return GROUPS[-1][0]


def reference_rst():
    """The whole reference as reStructuredText, one section per group of classes."""
    import yade.wrapper
    classes = []
    for name in plugin_class_names():
        if not hasattr(yade.wrapper, name):
            raise RuntimeError('Plugin.cpp registers %s, but yade.wrapper has no such class: is the '
                               'plugin built from this source (./yadew build)?' % name)
        classes.append(getattr(yade.wrapper, name))
    lines = ['.. py:currentmodule:: yade.wrapper', '']
    for title, _ in GROUPS:
        members = [c for c in classes if group_of(c) == title]
        if not members:
            continue
        lines += [title, '-' * len(title), '']
        for cls in members:
            lines += class_rst(cls)
    return lines


class YadeClasses(SphinxDirective):
    """``{yade-classes}``: every class of the plugin, read from the running YADE."""

    def run(self):
        self.env.note_dependency(PLUGIN_SOURCE)
        parsed = nodes.Element()
        nested_parse_with_titles(self.state, StringList(reference_rst(), 'yade.wrapper'), parsed)
        report_block_quotes(parsed)
        return parsed.children


def setup(app):
    app.add_directive('yade-classes', YadeClasses)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
