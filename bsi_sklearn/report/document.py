"""A small document model (headings, paragraphs, tables, figures) rendered to Markdown or HTML."""

from __future__ import annotations

import base64
import html
import re
from typing import NamedTuple

__all__ = ["Code", "Document", "render_html", "render_html_fragment", "render_markdown"]


class Code(NamedTuple):
    """Inline code (monospace, not escaped as prose) inside a paragraph, list item or cell."""

    text: str


class Document:
    """A tiny document model rendered to Markdown and to HTML (one source, two outputs).

    Blocks: ``("h", level, text)``, ``("p", inline)``, ``("pre", text)``, ``("formula", text)``
    (a formula in Unicode symbols, shown as display text: no LaTeX, nothing to fetch),
    ``("ul", [inline, ...])``, ``("table", header, rows)``, ``("figure", name, caption)``.
    Inline content is a str, a :class:`Code` or a list of both.

    Attributes
    ----------
    blocks : list of tuple
        The blocks, in reading order.

    Examples
    --------
    >>> doc = Document()
    >>> doc.add("h", 1, "Title")
    >>> doc.add("p", ["The formula ", Code("F(a)"), " holds."])
    >>> print(render_markdown(doc, {}), end="")
    # Title
    <BLANKLINE>
    The formula `F(a)` holds.
    """

    def __init__(self):
        self.blocks = []

    def add(self, *block):
        """Append one block (see the class docstring for the kinds)."""
        self.blocks.append(block)


_MD_SPECIAL = re.compile(r"([\\`*_\[\]<>|$#])")


def _md_text(text):
    return _MD_SPECIAL.sub(r"\\\1", str(text))


def _md_inline(inline):
    if isinstance(inline, Code):
        text = inline.text.replace("\n", " ")
        fence = "``" if "`" in text else "`"
        pad = " " if fence == "``" else ""
        return f"{fence}{pad}{text}{pad}{fence}"
    if isinstance(inline, list):
        return "".join(_md_inline(x) for x in inline)
    return _md_text(inline).replace("\n", " ")


def _html_inline(inline):
    if isinstance(inline, Code):
        return f"<code>{html.escape(inline.text)}</code>"
    if isinstance(inline, list):
        return "".join(_html_inline(x) for x in inline)
    return html.escape(str(inline))


def render_markdown(doc, figure_files):
    """Render a document as Markdown.

    Parameters
    ----------
    doc : Document
    figure_files : dict
        Figure name -> the path (relative to the Markdown file) its image is linked from.

    Returns
    -------
    str
    """
    out = []
    for block in doc.blocks:
        kind = block[0]
        if kind == "h":
            out.append(f"{'#' * block[1]} {_md_text(block[2])}")
        elif kind == "p":
            out.append(_md_inline(block[1]))
        elif kind == "pre":
            fence = "````" if "```" in block[1] else "```"
            out.append(f"{fence}text\n{block[1]}\n{fence}")
        elif kind == "formula":
            out.append(f"> **{_md_text(block[1])}**")
        elif kind == "ul":
            out.append("\n".join(f"- {_md_inline(item)}" for item in block[1]))
        elif kind == "table":
            header, rows = block[1], block[2]
            lines = ["| " + " | ".join(_md_inline(h) for h in header) + " |",
                     "|" + "|".join("---" for _ in header) + "|"]
            lines += ["| " + " | ".join(_md_inline(c) for c in row) + " |" for row in rows]
            out.append("\n".join(lines))
        elif kind == "figure":
            name, caption = block[1], block[2]
            out.append(f"![{_md_text(caption)}]({figure_files[name]})\n\n*{_md_text(caption)}*")
    return "\n\n".join(out) + "\n"


_CSS = """
.bsi-report { font-family: -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif;
  max-width: 60em; line-height: 1.45; color: #1b1b1b; }
.bsi-report table { border-collapse: collapse; margin: 0.6em 0; }
.bsi-report th, .bsi-report td { border: 1px solid #ccc; padding: 0.25em 0.6em;
  text-align: left; vertical-align: top; }
.bsi-report th { background: #f0f3f7; }
.bsi-report pre { background: #f6f8fa; padding: 0.6em; overflow-x: auto;
  white-space: pre-wrap; }
.bsi-report code { font-family: Menlo, Consolas, monospace; font-size: 0.92em; }
.bsi-report figure { margin: 1em 0; }
.bsi-report img { max-width: 100%; }
.bsi-report figcaption { font-style: italic; color: #555; }
.bsi-report .formula { font-family: 'Cambria Math', 'STIX Two Math', 'DejaVu Serif', serif;
  font-size: 1.15em; margin: 0.8em 1.5em; }
"""


def _render_html_body(doc, pngs):
    # The body only: a <div class="bsi-report"> styled by _CSS.
    out = ['<div class="bsi-report">']
    for block in doc.blocks:
        kind = block[0]
        if kind == "h":
            out.append(f"<h{block[1]}>{html.escape(block[2])}</h{block[1]}>")
        elif kind == "p":
            out.append(f"<p>{_html_inline(block[1])}</p>")
        elif kind == "pre":
            out.append(f"<pre><code>{html.escape(block[1])}</code></pre>")
        elif kind == "formula":
            out.append(f'<p class="formula">{html.escape(block[1])}</p>')
        elif kind == "ul":
            items = "".join(f"<li>{_html_inline(item)}</li>" for item in block[1])
            out.append(f"<ul>{items}</ul>")
        elif kind == "table":
            header, rows = block[1], block[2]
            head = "".join(f"<th>{_html_inline(h)}</th>" for h in header)
            body = "".join(
                "<tr>" + "".join(f"<td>{_html_inline(c)}</td>" for c in row) + "</tr>"
                for row in rows
            )
            out.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
        elif kind == "figure":
            name, caption = block[1], block[2]
            data = base64.b64encode(pngs[name]).decode("ascii")
            cap = html.escape(caption)
            out.append(f'<figure><img src="data:image/png;base64,{data}" alt="{cap}"/>'
                       f"<figcaption>{cap}</figcaption></figure>")
    out.append("</div>")
    return "\n".join(out)


def render_html(doc, pngs, title):
    """Render a document as one self-contained HTML page (figures embedded as base64 PNG).

    Parameters
    ----------
    doc : Document
    pngs : dict
        Figure name -> PNG bytes.
    title : str
        The page title (``<title>``).

    Returns
    -------
    str
    """
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
        f"<title>{html.escape(title)}</title>\n<style>{_CSS}</style>\n</head>\n"
        f"<body>\n{_render_html_body(doc, pngs)}\n</body>\n</html>\n"
    )


def render_html_fragment(doc, pngs):
    """Render a document as an HTML fragment (style and body, no page), for notebooks.

    Parameters
    ----------
    doc : Document
    pngs : dict
        Figure name -> PNG bytes.

    Returns
    -------
    str
    """
    return f"<style>{_CSS}</style>\n{_render_html_body(doc, pngs)}"
