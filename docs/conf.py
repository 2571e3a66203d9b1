# The documentation site (scripts/docs.sh builds it into out/docs; CI runs that with warnings as
# errors). Sphinx with MyST: the pages stay Markdown that reads on GitHub as well, and autodoc
# takes the Python reference from the module itself (docs/decisions.md, "The documentation site").
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(root / "docs" / "_ext"))

project = "panoproj"
author = "the panoproj authors"
copyright = "the panoproj authors (MIT)"
release = version = re.search(r"project\(panoproj VERSION ([0-9.]+)", (root / "CMakeLists.txt").read_text()).group(1)

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.mathjax", "header_reference"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 4  # links such as projections.md#photometry
exclude_patterns = ["_ext"]

# Formulas without a CDN: scripts/docs.sh copies npm's MathJax 3 into the built site.
mathjax_path = "mathjax/tex-svg.js"
mathjax3_config = {"options": {"enableMenu": False}, "loader": {"load": []}}

html_theme = "alabaster"
html_title = "panoproj"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_theme_options = {"page_width": "1200px", "sidebar_width": "230px", "body_max_width": "none", "fixed_sidebar": True,
                      "description": "Image-space reprojection between panoramic, fisheye, pinhole, cubemap and map projections"}
html_sidebars = {"**": ["about.html", "navigation.html", "searchbox.html"]}
html_show_sourcelink = False

autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_default_options = {"members": True, "undoc-members": False}
# The header reference reads the installed set (lib/include/panoproj).
header_reference_root = str(root / "lib" / "include")


_ENTRY = re.compile(r"^\s*[A-Za-z_][A-Za-z0-9_]*(\s*=\s*[^:]*)?:\s")


def _lists_as_text(app, what, name, obj, options, lines):
    """The docstrings are written for help(): a heading line ending in ':' followed by
    'key: text' or 'key = default: text' entries (wrapped lines indented). Such a block is shown
    as preformatted text, as help() shows it; the prose around it stays reStructuredText."""
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        nxt = next((l for l in lines[i + 1:] if l.strip()), "")
        if line.rstrip().endswith(":") and not line.rstrip().endswith("::") and _ENTRY.match(nxt):
            out += [line.rstrip() + ":", ""]
            i += 1
            while i < len(lines) and (lines[i].strip() or (i + 1 < len(lines) and lines[i + 1].startswith(" "))):
                out.append("    " + lines[i])
                i += 1
            out.append("")
            continue
        out.append(line)
        i += 1
    lines[:] = out


def _every_name_documented(app, exception):
    """The Python page documents every name dir(panoproj) lists (a new one without a docstring
    fails the build)."""
    if exception is not None or app.builder.name != "html":
        return
    import panoproj

    page = pathlib.Path(app.outdir, "python.html").read_text(encoding="utf-8")
    missing = [n for n in dir(panoproj) if not n.startswith("_") and f'id="panoproj.{n}"' not in page]
    if missing:
        from sphinx.util import logging

        logging.getLogger(__name__).warning("the Python API page lacks %s (docs/python.md)", ", ".join(missing))


def setup(app):
    app.connect("autodoc-process-docstring", _lists_as_text)
    app.connect("build-finished", _every_name_documented)
