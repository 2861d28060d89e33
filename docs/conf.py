"""Sphinx configuration of the reviewer's site (built by ``tools/reviewer_site.py``; ``make report``).

The sources are staged in ``build/site-src`` (this folder, the executed notebooks, figures, data and the
pages generated from data); the HTML goes to ``build/report``. Executed notebooks are rendered as they
are (MyST-NB, execution off). Nothing is loaded from the web: no MathJax (the notebooks carry no LaTeX),
the theme's fonts and scripts are its own static files.
"""

project = "mtcal"
author = "mtcal contributors"
copyright = "mtcal contributors (MIT)"
extensions = ["myst_nb"]
exclude_patterns = ["_build", "conf.py", "**/.ipynb_checkpoints"]
suppress_warnings = ["mystnb.unknown_mime_type"]

# MyST-NB: render the notebooks `make reproduce` executed; never run them here
nb_execution_mode = "off"
nb_merge_streams = True
myst_heading_anchors = 6
myst_enable_extensions = []

html_theme = "sphinx_book_theme"
html_title = "mtcal — reproduction of the papers"
html_static_path = ["_static"]
html_css_files = ["site.css"]
html_theme_options = {
    "show_toc_level": 2,
    "use_download_button": False,
    "use_fullscreen_button": False,
    "home_page_in_toc": True,
    "secondary_sidebar_items": {"**": ["page-toc"], "index": []},  # the front page's scoreboard gets the width
}
html_context = {"default_mode": "light"}  # a fixed start mode (an empty stored one logs a console error)
html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None
# no MathJax: an unused math renderer would load it from a CDN
html_math_renderer = "html_math_off"


def _no_math(app):
    """A math renderer that loads nothing (the site has no math; a page that had some would show the TeX)."""
    from sphinx.ext.mathjax import html_visit_displaymath, html_visit_math

    app.add_html_math_renderer("html_math_off", (html_visit_math, None), (html_visit_displaymath, None))


def setup(app):
    _no_math(app)
