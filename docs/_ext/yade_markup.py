"""YADE's docstring markup, as YADE's own manual reads it, for our docstrings and pages.

``:yref:`target``` or ``:yref:`text<target>```: a reference to a YADE class, attribute or function.
- ``viscbridge...`` (``:yref:`viscbridge.engines()```): our Python reference (docs/reference/python);
- a class the plugin registers (``:yref:`ViscBridgeGuard```, ``:yref:`ViscBridgeGuard.rebaseline```):
  our class reference (docs/reference/classes), where it must exist;
- anything else in ``yade.wrapper`` (``:yref:`O.stopAtTime<Omega.stopAtTime>```): YADE's online
  class reference, https://yade-dem.org/doc/yade.wrapper.html#yade.wrapper.Omega.stopAtTime, once
  checked against the running YADE; ``yade.MODULE.NAME``: YADE's page of that module.
A target found nowhere fails the build (a warning, and the build runs with -W), so a renamed
attribute cannot leave a dead link behind.

``:ydefault:`` and ``:yattrtype:`` (YADE appends them to every attribute's docstring; the class
reference shows them as the attribute's default and type) render as "default: ..." / "type: ...".

``yname``, the default role (conf.py), shows `name` as code and links it where it names one of our
classes, attributes or functions.

``$...$`` (LaTeX, as YADE's docstrings write formulas) becomes ``:math:`...``` in docstrings
(:func:`docstring_to_rst`; the Markdown pages write formulas in Unicode and are left alone).
"""
import importlib
import re

from docutils import nodes
from sphinx import addnodes
from sphinx.util import logging

logger = logging.getLogger(__name__)

YADE_DOC = 'https://yade-dem.org/doc/'
EXPLICIT = re.compile(r'^(.*?)\s*<(.+)>$', re.S)
# ``literal`` spans (kept as they are) or $formula$ (not $$, not across lines)
LITERAL_OR_MATH = re.compile(r'(``.+?``)|(?<![\\$])\$([^$\n]+?)\$(?!\$)')


def docstring_to_rst(text):
    """A YADE-style docstring as reStructuredText: $formula$ as :math:`formula`, except in ``code``
    and in literal blocks (the indented block after a line ending in '::': a shell's $VARIABLE)."""
    def convert(m):
        if m.group(1):
            return m.group(1)
        return ':math:`%s`' % m.group(2).strip()
    out, literal_margin, opens_literal = [], None, None
    for line in text.split('\n'):
        margin = len(line) - len(line.lstrip())
        if line.strip():
            if literal_margin is not None and margin <= literal_margin:
                literal_margin = None  # the literal block ended
            if literal_margin is None and opens_literal is not None and margin > opens_literal:
                literal_margin = opens_literal  # the block after "::" began
            opens_literal = margin if literal_margin is None and line.rstrip().endswith('::') else None
        out.append(line if literal_margin is not None else LITERAL_OR_MATH.sub(convert, line))
    return '\n'.join(out)


def report_block_quotes(parsed):
    """Warn of every block quote in generated reference text: in a docstring it is an example whose
    paragraph does not end with '::', which the manual would show as running text."""
    for quote in parsed.findall(nodes.block_quote):
        logger.warning('an indented block that is not code (%s...): end the paragraph before an example '
                       'with "::", else the manual shows it as running text', ' '.join(quote.astext().split())[:40],
                       location=quote, type='viscbridge', subtype='block_quote')


def split_target(text):
    """(shown text, target) of a role's text: 'O.stopAtTime<Omega.stopAtTime>' or 'ViscBridgeGuard'."""
    m = EXPLICIT.match(text.strip())
    if m:
        return m.group(1), m.group(2).strip()
    return text.strip(), text.strip()


def normalise(target):
    """The dotted name a target means: '::' as '.', without a call's parentheses
    ('viscbridge.engines(integration=\'implicit\')': viscbridge.engines)."""
    return re.sub(r'\(.*\)$', '', target.replace('::', '.'), flags=re.S)


def yref_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    shown, target = split_target(text)
    target = normalise(target)
    if not target.startswith('viscbridge') and not target.startswith('yade.'):
        target = 'yade.wrapper.' + target
    # a cross-reference resolved by the Python domain (our reference); what it does not find is
    # YADE's (missing_reference below) or an error
    ref = addnodes.pending_xref(rawtext, refdomain='py', reftype='obj', reftarget=target,
                                refexplicit=True, refwarn=True, yref=True)
    ref += nodes.literal(rawtext, shown, classes=['xref', 'py', 'yref'])
    ref['refdoc'] = inliner.document.settings.env.docname
    return [ref], []


def name_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    """The default role, `name` (docstrings write a parameter, an attribute or a class so): code, and
    a link where it names something of our reference (`ViscBridgeSpray`,
    `Ip2_FrictMat_FrictMat_ViscBridgePhys.liquidModel`, `viscbridge.liquid.spray()`)."""
    from yade_classes import plugin_class_names  # (it uses docstring_to_rst from here)
    target = normalise(text)
    first = target.split('.')[0]
    if first != 'viscbridge' and first not in plugin_class_names():
        return [nodes.literal(rawtext, text)], []
    ref = addnodes.pending_xref(rawtext, refdomain='py', reftype='obj', refexplicit=True, soft=True,
                                reftarget=target if first == 'viscbridge' else 'yade.wrapper.' + target)
    ref['refdoc'] = inliner.document.settings.env.docname
    ref += nodes.literal(rawtext, text, classes=['xref', 'py'])
    return [ref], []


def yade_has(target):
    """Whether the running YADE has `target` ('yade.wrapper.Omega.stopAtTime', 'yade.utils.sphere')."""
    parts = target.split('.')
    for n in range(len(parts), 0, -1):  # the longest importable module, then attributes
        try:
            obj = importlib.import_module('.'.join(parts[:n]))
        except ImportError:
            continue
        try:
            for attr in parts[n:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return False
        return True
    return False


def yade_url(target):
    """YADE's online reference page and anchor of a 'yade.MODULE[.NAME...]' target."""
    module = '.'.join(target.split('.')[:2])
    return '%s%s.html#%s' % (YADE_DOC, module, target)


def missing_reference(app, env, node, contnode):
    """A :yref: that our reference does not hold, or a type in the signature of one of our classes'
    methods (``of(body: Body)``): YADE's online reference, if YADE has it."""
    from yade_classes import plugin_class_names  # (it uses docstring_to_rst from here)
    if node.get('refdomain') != 'py':
        return None
    if node.get('soft'):
        return contnode  # `name` that is not in our reference after all: code, without a link
    target = node['reftarget']
    if not node.get('yref'):
        if node.get('py:module') != 'yade.wrapper' or '.' in target:
            return None
        target = 'yade.wrapper.' + target
    parts = target.split('.')
    if parts[0] == 'viscbridge' or parts[:2] == ['yade', 'wrapper'] and parts[2] in plugin_class_names():
        return None  # ours, so it had to be in our reference: Sphinx reports it
    if not yade_has(target):
        if node.get('yref'):
            logger.warning(':yref:`%s`: YADE %s has no %s', node.astext(), _yade_version(), target,
                           location=node, type='yref', subtype='missing')
            return contnode
        return None
    ref = nodes.reference('', '', internal=False, refuri=yade_url(target), reftitle=target)
    ref += contnode
    return ref


def _yade_version():
    try:
        from yade import config
        return config.version
    except ImportError:
        return '(not importable)'


def ydefault_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    return [nodes.Text('default: '), nodes.literal(rawtext, text)], []


def yattrtype_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    return [nodes.Text('type: '), nodes.literal(rawtext, text)], []


def setup(app):
    app.add_role('yref', yref_role)
    app.add_role('yname', name_role)
    app.add_role('ydefault', ydefault_role)
    app.add_role('yattrtype', yattrtype_role)
    app.connect('missing-reference', missing_reference)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
