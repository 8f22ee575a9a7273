"""Sphinx configuration of the ViscBridge manual: the Markdown pages of docs/ (MyST) and a reference
generated from the live classes, so the build runs where ``import yade`` loads the plugin
(``./yadew docs``, i.e. tools/build_manual.py inside the environment).

Every module in docs/_ext/ is a Sphinx extension and is loaded: add one there and it is used.
"""
import glob
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
EXTENSION_DIR = os.path.join(HERE, '_ext')
sys.path.insert(0, EXTENSION_DIR)

project = 'ViscBridge'
author = 'the ViscBridge developers'
copyright = author
# The commit the manual was built from: ./yadew docs reads it with git on the host (the environment
# has no git) and passes it on; a build started otherwise says so.
release = version = os.environ.get('VISCBRIDGE_MANUAL_VERSION', 'unversioned build')

extensions = ['myst_parser', 'sphinx.ext.autodoc', 'sphinx.ext.mathjax'] + sorted(
    os.path.splitext(os.path.basename(p))[0] for p in glob.glob(os.path.join(EXTENSION_DIR, '*.py')))

# the pages are Markdown; the generated reference pages (docs/reference) are reStructuredText,
# which their directives produce
source_suffix = {'.md': 'markdown', '.rst': 'restructuredtext'}
root_doc = 'index'
# docs/data, docs/perf and docs/figures hold measurements and figures, not pages (the figures a page
# shows are still copied: images follow their references, not this list).
exclude_patterns = ['_build', '_ext', '_static', 'data', 'perf', 'figures', '**/__pycache__']

# MyST: the pages' [text](#section) and [text](page.md#section) links go to headings of levels 1-4.
myst_heading_anchors = 4

# Docstrings write `name` for a parameter, an attribute or a class: shown as code, linked where it is
# one of ours (docs/_ext/yade_markup.py).
default_role = 'yname'
autodoc_default_options = {'member-order': 'bysource'}
autodoc_typehints = 'signature'
# Every reference must resolve (to our reference, or by :yref: to YADE's); -W turns a miss into an error.
nitpicky = True

html_theme = 'sphinx_rtd_theme'
html_title = 'ViscBridge manual'
html_theme_options = {'navigation_depth': 3}
html_show_sourcelink = False
html_copy_source = False
html_static_path = ['_static']
html_css_files = ['viscbridge.css']
