"""Anchors for the equation labels of docs/physics.md (P14, A1b, E5, L6b, R3, ...) and its numbered
sections (§7, §7a), so that a page, a docstring or a reader's bookmark can point at one:
physics.html#p14, physics.html#sec-7, and in Markdown ``[P14](physics.md#p14)``; and links from the
reference pages' docstrings, which cite them in plain text ("(P14)", "physics.md §11, L6"), to them.

physics.md stays plain Markdown (readable on GitHub): a label is defined where it is first written in
bold — ``**P14**``, ``- **P0a (arms ...).**``, ``**P1, P2 (...)**``, ``(**A4a**, ...)``, as
tests/unit/test_docs.py finds the definitions it checks citations against — and this transform gives
that bold text the id ``p14`` (the label in lower case), a heading "7a. ..." the id ``sec-7a``, and
registers them with MyST beside the heading anchors, so that links to them resolve (and a link to a
label that does not exist fails the build).  A range such as ``**P0–P22**`` defines nothing.
"""
import re

from docutils import nodes
from docutils.transforms import Transform
from sphinx.transforms.post_transforms import SphinxPostTransform

# the tags of tests/unit/test_docs.py, plus the liquid rules L0-L7 and the accuracy rules A1-A5
TAG = r'(?:P\d{1,2}[a-c]?|[RAEL]\d{1,2}[a-c]?)'
# bold text that is a label or a list of labels, then nothing, a space, '.', ')' or ','
DEFINITION = re.compile(r'^\(?(%s(?:\s*,\s*%s)*)(?=$|[\s.),])' % (TAG, TAG))
# a numbered section's heading: "7a. Accuracy as the input ..."
SECTION = re.compile(r'^(\d+[a-z]?)\. ')
# a citation in running text: "physics.md §7", "§11", or a label
CITATION = re.compile(r'((?:docs/)?physics\.md\s*)?§(\d+[a-z]?)\b|\b(%s)\b' % TAG)


def labels_defined_by(text):
    """The labels a bold text defines: ['P1', 'P2'] for 'P1, P2 (equations of motion) [paper].'."""
    m = DEFINITION.match(text.strip())
    return re.findall(TAG, m.group(1)) if m else []


class EquationAnchors(Transform):
    """Gives each label's first bold definition its id and registers it as a MyST anchor."""

    # before MyST's ResolveAnchorIds (879), so that [P14](#p14) within the page resolves too
    default_priority = 870

    def apply(self):
        env = self.document.settings.env
        if env.docname not in env.config.equation_anchor_pages:
            return
        slugs = getattr(self.document, 'myst_slugs', None)
        if slugs is None:
            slugs = {}
        for strong in list(self.document.findall(nodes.strong)):
            for label in labels_defined_by(strong.astext()):
                anchor = label.lower()
                if anchor in slugs or anchor in self.document.ids:
                    continue  # a later mention, or a heading of that name
                if strong['ids']:  # "P1, P2": HTML shows one id per element, so P2 gets a span of its own
                    target = nodes.inline('', '', ids=[anchor])
                    strong.parent.insert(strong.parent.index(strong), target)
                else:
                    target = strong
                    strong['ids'].append(anchor)
                self.document.ids[anchor] = target
                slugs[anchor] = (strong.line or 0, anchor, label)
        for section in self.document.findall(nodes.section):
            m = SECTION.match(section[0].astext()) if section.children else None
            if m and 'sec-' + m.group(1) not in self.document.ids:
                anchor = 'sec-' + m.group(1)
                section['ids'].append(anchor)
                self.document.ids[anchor] = section
                slugs[anchor] = (section.line or 0, anchor, '§' + m.group(1))
        self.document.myst_slugs = slugs
        env.metadata[env.docname]['myst_slugs'] = slugs


class CitationLinks(SphinxPostTransform):
    """In the pages of ``equation_link_pages`` (the generated reference), every citation of a label
    or a section that physics.md defines becomes a link to it; other text is left alone."""

    default_priority = 900

    def run(self):
        if self.env.docname not in self.config.equation_link_pages:
            return
        for page in self.config.equation_anchor_pages:
            anchors = self.env.metadata.get(page, {}).get('myst_slugs', {})
            uri = self.app.builder.get_relative_uri(self.env.docname, page)
            for text in list(self.document.findall(nodes.Text)):
                if not self.linkable(text):
                    continue
                replaced = self.link(text.astext(), anchors, uri)
                if replaced:
                    text.parent.replace(text, replaced)

    @staticmethod
    def linkable(text):
        """Running text: not code, math, a link, a title or a signature."""
        node = text.parent
        while node is not None:
            if isinstance(node, (nodes.literal, nodes.literal_block, nodes.math, nodes.math_block, nodes.reference,
                                 nodes.title, nodes.raw)) or node.tagname.startswith('desc_sig') \
                    or node.tagname in ('desc_signature', 'pending_xref'):
                return False
            node = node.parent
        return True

    @staticmethod
    def link(text, anchors, uri):
        """The nodes of `text` with its citations linked, or None when it cites nothing defined."""
        pieces, start = [], 0
        for m in CITATION.finditer(text):
            anchor = ('sec-' + m.group(2)) if m.group(2) else m.group(3).lower()
            if anchor not in anchors:
                continue
            pieces.append(nodes.Text(text[start:m.start()]))
            pieces.append(nodes.reference(m.group(0), m.group(0), internal=True, refuri='%s#%s' % (uri, anchor),
                                          classes=['physics-citation']))
            start = m.end()
        if not pieces:
            return None
        pieces.append(nodes.Text(text[start:]))
        return pieces


def setup(app):
    app.add_config_value('equation_anchor_pages', ['physics'], 'env', types=[list])
    app.add_config_value('equation_link_pages', ['reference/classes', 'reference/python'], 'env', types=[list])
    app.add_transform(EquationAnchors)
    app.add_post_transform(CitationLinks)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
