"""The C++ reference page's body: every installed public header (conf.py's
header_reference_root/panoproj), one section each: its opening comment as prose, then the
declarations with their comments as highlighted C++. The headers' comments are the contract
(plain `//`, the codebase's habit), so the page is read from them as they are."""

import pathlib
import re

from docutils import nodes
from sphinx.util.docutils import SphinxDirective


def _split(text):
    """(opening comment paragraphs, the rest from the first line that is not an include)."""
    lines = text.splitlines()
    i = 0
    if lines and lines[0].startswith("#pragma once"):
        i = 1
    comment = []
    while i < len(lines) and lines[i].startswith("//"):
        comment.append(lines[i][2:].removeprefix(" ").rstrip())
        i += 1
    while i < len(lines) and (lines[i].startswith("#include") or not lines[i].strip()):
        i += 1
    paragraphs = [p.strip("\n") for p in "\n".join(comment).split("\n\n")]
    return [p for p in paragraphs if p.strip()], "\n".join(lines[i:]).rstrip() + "\n"


def _order(root):
    return sorted(root.glob("*.hpp")) + sorted(root.glob("*/*.hpp"))


class HeaderReference(SphinxDirective):
    has_content = False

    def run(self):
        base = pathlib.Path(self.config.header_reference_root)
        out = []
        summary = nodes.bullet_list()
        for path in _order(base / "panoproj"):
            self.env.note_dependency(str(path))
            name = path.relative_to(base).as_posix()
            ident = "header-" + re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")
            prose, code = _split(path.read_text(encoding="utf-8"))
            first = " ".join(prose[0].split()).split(". ")[0].rstrip(".") + "." if prose else ""
            ref = nodes.reference("", "", nodes.literal(text=name), refid=ident)
            summary += nodes.list_item("", nodes.paragraph("", "", ref, nodes.Text(": " + first if first else "")))
            section = nodes.section(ids=[ident], names=[nodes.fully_normalize_name(name)])
            section += nodes.title(text=name)
            for paragraph in prose:  # a list or a table in the comment keeps its lines
                laid_out = any(line.startswith(("-", " ")) for line in paragraph.split("\n")[1:])
                section += (nodes.literal_block(paragraph, paragraph, language="none") if laid_out
                            else nodes.paragraph(text=" ".join(paragraph.split())))
            section += nodes.literal_block(code, code, language="cpp")
            out.append(section)
        return [summary] + out


def setup(app):
    app.add_config_value("header_reference_root", "", "env")
    app.add_directive("header-reference", HeaderReference)
    return {"version": "1", "parallel_read_safe": True}
