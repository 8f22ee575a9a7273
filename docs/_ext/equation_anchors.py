"""Anchors for the equation labels of docs/physics.md (P14, A1b, E5, L6b, R3, ...), so that a page,
a docstring or a reader's bookmark can point at one: physics.html#p14, and in Markdown
``[P14](physics.md#p14)``.

physics.md stays plain Markdown (readable on GitHub): a label is defined where it is first written in
bold at the start of its statement — ``**P14**``, ``- **P0a (arms ...).**``, ``**P1, P2 (...)**``,
``(**A4a**, ...)``, the same rule tests/unit/test_docs.py checks citations against — and this
transform gives that bold text the id ``p14`` (the label in lower case), and registers it with MyST
beside the heading anchors so that links to it resolve (and a link to a label that does not exist
fails the build).  A range such as ``**P0–P22**`` defines nothing.
"""
import re

from docutils import nodes
from docutils.transforms import Transform

# the tags of tests/unit/test_docs.py, plus the liquid rules L0-L7 and the accuracy rules A1-A5
TAG = r'(?:P\d{1,2}[a-c]?|[RAEL]\d{1,2}[a-c]?)'
# bold text that is a label or a list of labels, then nothing, a space, '.', ')' or ','
DEFINITION = re.compile(r'^\(?(%s(?:\s*,\s*%s)*)(?=$|[\s.),])' % (TAG, TAG))


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
        self.document.myst_slugs = slugs
        env.metadata[env.docname]['myst_slugs'] = slugs


def setup(app):
    app.add_config_value('equation_anchor_pages', ['physics'], 'env', types=[list])
    app.add_transform(EquationAnchors)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
