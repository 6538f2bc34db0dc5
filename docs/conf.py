# Sphinx configuration of the sluice documentation: `make docs` builds it into build/docs/.
# MyST Markdown pages, a theme that ships with Sphinx, nothing fetched from the network. The case-file
# reference and the commands' options come from the sluice binary at build time (_ext/sluice_docs.py;
# $SLUICE_BIN, by default build/release/sluice).
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))

project = "sluice"
author = "the sluice authors"
copyright = "the sluice authors"

extensions = ["myst_parser", "sluice_docs"]
source_suffix = {".md": "markdown"}
root_doc = "index"
# Blocks without a language (program output, error messages) are shown as they are, not highlighted.
highlight_language = "text"
# Quotes as typed: the reference's allowed values ("dynamic", "adami") are what a case file holds.
smartquotes = False
exclude_patterns = ["_build", "_ext", "README.md", "generated"]  # generated/: included by the pages

# Links to headings of other pages (`physics.md#walls`), definition lists, and field lists (the case
# reference's facts about each key).
myst_heading_anchors = 3
myst_enable_extensions = ["deflist", "colon_fence", "fieldlist"]

html_theme = "alabaster"
html_theme_options = {
    "page_width": "auto",
    "body_max_width": "none",
    "sidebar_width": "230px",
    "fixed_sidebar": False,
    "show_relbars": True,
    "description": "SPH for free-surface water flows",
}
html_static_path = ["_static"]
html_css_files = ["sluice.css"]
html_title = "sluice documentation"
html_show_sourcelink = False
html_sidebars = {"**": ["about.html", "navigation.html", "relations.html", "searchbox.html"]}
