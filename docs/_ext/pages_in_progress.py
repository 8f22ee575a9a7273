"""The index may list pages that are being written on other branches (conf.py's
``manual_pages_in_progress``): a toctree leaves such a page out while its file is missing, and lists
it as soon as it exists.  A missing page that is not in that list is still an error, as in Sphinx."""
from docutils.statemachine import StringList
from sphinx.directives.other import TocTree
from sphinx.util import logging

logger = logging.getLogger(__name__)


class TocTreeWithPagesInProgress(TocTree):
    """Sphinx's toctree, without the entries of missing pages in progress."""

    def parse_content(self, toctree):
        pending = set(self.config.manual_pages_in_progress)
        kept = StringList()
        for line, (source, offset) in zip(self.content, self.content.items):
            name = line.strip()
            if name in pending and name not in self.env.found_docs:
                logger.info('toctree: %s is in progress on another branch, left out until it exists', name)
                continue
            kept.append(line, source, offset)
        self.content = kept
        super().parse_content(toctree)



def setup(app):
    app.add_config_value('manual_pages_in_progress', [], 'env', types=[list])
    app.add_directive('toctree', TocTreeWithPagesInProgress, override=True)
    return {'parallel_read_safe': True, 'parallel_write_safe': True}
