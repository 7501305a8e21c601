"""Markdown the report writes, kept readable in a plain editor (issue 48): no table cell over
MAX_CELL characters and no line over MAX_LINE. `fit` rewrites a section's lines to that shape
without losing a word: long prose is wrapped (list items keep their indentation), a table cell
over MAX_CELL moves below its table as a numbered note ("note 3" in the cell), and so do the
longest cells of a row still over MAX_LINE. Standard library only."""

import re
import textwrap

MAX_CELL = 200
MAX_LINE = 400
WRAP = 100   # prose is wrapped at this width

_LINK = re.compile(r"(!?)\[([^\]]*)\]\(([^)\s]+)\)")


def _cells(row):
    """The cells of a table row ("| a | b |"), split on | not escaped."""
    body = row.strip()
    body = body[1:] if body.startswith("|") else body
    body = body[:-1] if body.endswith("|") and not body.endswith("\\|") else body
    return [c.strip() for c in re.split(r"(?<!\\)\|", body)]


def _row(cells):
    return "| " + " | ".join(cells) + " |"


def _wrap(line, width=WRAP):
    """A prose line wrapped at `width` (a list item's continuation lines indented under its
    text); headings, images and code stay as they are (an image line is short by itself)."""
    if len(line) <= width or line.startswith(("#", "!", "```", "    ")):
        return [line]
    m = re.match(r"(\s*(?:[-*]|\d+\.)\s+)", line)
    lead = m.group(1) if m else re.match(r"\s*", line).group(0)
    return textwrap.wrap(line, width, initial_indent="", subsequent_indent=" " * len(lead),
                         break_long_words=False, break_on_hyphens=False) or [line]


def _fit_table(rows, notes):
    """A table's rows with each cell over MAX_CELL, then the longest cells of a row over
    MAX_LINE, replaced by "note N" and their text appended to `notes`."""
    out = []
    for i, row in enumerate(rows):
        cells = _cells(row)
        if i == 1 and all(set(c) <= set("-: ") for c in cells):
            out.append(row)
            continue
        for j, c in enumerate(cells):
            if len(c) > MAX_CELL:
                notes.append(c)
                cells[j] = f"note {len(notes)}"
        while len(_row(cells)) > MAX_LINE:
            j = max(range(len(cells)), key=lambda k: len(cells[k]))
            if len(cells[j]) <= len("note 999"):
                break
            notes.append(cells[j])
            cells[j] = f"note {len(notes)}"
        out.append(_row(cells))
    return out


def fit(lines, width=WRAP):
    """`lines` (one markdown line each; an entry may hold newlines) with no table cell over
    MAX_CELL and no line over MAX_LINE: prose wrapped at `width` (at most MAX_LINE), long cells
    moved to notes below their table."""
    width = min(width, MAX_LINE)
    flat = [x for line in lines for x in str(line).split("\n")]
    out, i, fence = [], 0, False
    while i < len(flat):
        line = flat[i]
        if line.startswith("```"):
            fence = not fence
        if not fence and line.lstrip().startswith("|"):
            j = i
            while j < len(flat) and flat[j].lstrip().startswith("|"):
                j += 1
            notes = []
            out += _fit_table(flat[i:j], notes)
            if notes:
                out.append("")
                for n, text in enumerate(notes, 1):
                    out += _wrap(f"- note {n}: {text}", width)
            i = j
            continue
        out += [line] if fence else _wrap(line, width)
        i += 1
    return out


def problems(text, name="report"):
    """Every breach of the shape in a markdown text: lines over MAX_LINE, table cells over
    MAX_CELL; one message each."""
    bad = []
    for n, line in enumerate(text.splitlines(), 1):
        if len(line) > MAX_LINE:
            bad.append(f"{name}:{n}: line of {len(line)} characters (at most {MAX_LINE})")
        if line.lstrip().startswith("|"):
            for c in _cells(line):
                if len(c) > MAX_CELL:
                    bad.append(f"{name}:{n}: table cell of {len(c)} characters "
                               f"(at most {MAX_CELL})")
    return bad


def links(text):
    """[(is_image, target)] of the relative links and images of a markdown text (no URLs, no
    in-page anchors)."""
    return [(bool(b), t.split("#")[0]) for b, _, t in _LINK.findall(text)
            if not re.match(r"[a-z]+:", t) and not t.startswith("#")]


def relink(lines, prefix):
    """Lines with every relative link and image target prefixed (an appendix one folder below
    the report links the report's files through "../")."""
    def sub(m):
        b, label, t = m.groups()
        if re.match(r"[a-z]+:", t) or t.startswith(("#", "/")):
            return m.group(0)
        return f"{b}[{label}]({prefix}{t})"
    return [_LINK.sub(sub, line) for line in lines]
