"""Reading XML that may be hostile, and knowing where each element was written.

Task files come from anywhere, so the parser expands no entities, loads no DTD, touches
no network, and refuses files that are too big, too deep, binary or carry a DOCTYPE at
all (an ATD never needs one). Every refusal is one diagnostic, never an exception.
"""

from __future__ import annotations

import codecs
import re
from bisect import bisect_right
from dataclasses import dataclass
from itertools import repeat
from pathlib import Path

from lxml import etree

from atd.model.diagnostics import Diagnostic, error
from atd.model.files import InputError, InputTooBig, read_capped
from atd.model.task import Location

MAX_BYTES = 32 * 1024 * 1024  # a 10,000-state task is about 4 MB
MAX_DEPTH = 256  # libxml2 refuses deeper documents unless huge_tree is set; an ATD nests 4 levels

# A start tag's `<name`, or a comment, CDATA section or processing instruction to pass over whole
# (group 1 is set for start tags only): one scan finds every element's opening in document order.
_OPENING_OR_SKIPPED = re.compile(rb"<([A-Za-z_])|<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>", re.S)
_DOCTYPE = re.compile(rb"<!DOCTYPE|<!ENTITY", re.I)
_NEWLINE = re.compile(rb"\n")
_DOCUMENT_STARTS = b"< \t\r\n"  # a declaration or the root element, or white space before the root
_UTF16_LE_STARTS = {bytes([c, 0]) for c in _DOCUMENT_STARTS}
_UTF16_BE_STARTS = {bytes([0, c]) for c in _DOCUMENT_STARTS}
_DECLARED_ENCODING = re.compile(r"""^(<\?xml[^>]*?encoding\s*=\s*)(["'])[^"']*\2""")
# libxml2's fixed limits (without huge_tree): the words its messages use, and ours.
_PARSER_LIMITS = (
    (("Comment too big", "Text node too long", "Buffer size limit", "Huge input lookup", "XML_PARSE_HUGE"),
     "a comment, text or attribute value is longer than the 10,000,000 characters an ATD may hold in one place",
     "shorten it, or split the task into sub-tasks (type=\"task\")"),
    (("Name too long",),
     "an element or attribute name is longer than the 50,000 characters an ATD may use",
     "use the element and attribute names of docs/atd-format.md"),
)


@dataclass
class ParsedXml:
    """A parsed document and where every element's start tag begins."""

    root: etree._Element
    file: str
    _starts: dict[etree._Element, Location]

    def loc(self, element: etree._Element) -> Location:
        return self._starts.get(element) or Location(self.file, element.sourceline or 0, 1)


def _parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_pis=True,
        remove_comments=True,  # no reader needs them, and an element's children are then elements only
    )


def _line_col(data: bytes, offset: int) -> tuple[int, int]:
    """(line, column) of one byte offset."""
    return data.count(b"\n", 0, offset) + 1, offset - (data.rfind(b"\n", 0, offset) + 1) + 1


def _tag_starts(data: bytes, root: etree._Element, file: str) -> dict[etree._Element, Location]:
    """Pair elements in document order with the `<tag` openings in the text.

    lxml reports the line where a start tag *ends*; authors expect the line where it
    begins, and a column too, so we find the openings ourselves. Lines by bisection of
    the line starts, and Locations made without NamedTuple's Python-level constructor: a
    40,000-state task has 160,000 elements (issue 12).
    """
    openings = [m.start() for m in _OPENING_OR_SKIPPED.finditer(data) if m.start(1) >= 0]
    elements = list(root.iter(etree.Element))
    if len(elements) != len(openings):
        return {}
    line_starts = [0]
    line_starts += [m.end() for m in _NEWLINE.finditer(data)]
    lines = map(bisect_right, repeat(line_starts), openings)
    make = tuple.__new__
    return dict(zip(elements, [make(Location, (file, line, offset - line_starts[line - 1] + 1))
                               for line, offset in zip(lines, openings)]))


def _too_big(size: int, file: str) -> Diagnostic:
    return error(
        "ATD002",
        f"file is {size / 1e6:.1f} MB, larger than the {MAX_BYTES // 2**20} MiB an ATD may be",
        Location(file, 1, 1),
        'split the task into sub-tasks (type="task") or check that this is the right file',
    )


def _utf16_as_utf8(data: bytes) -> bytes:
    """UTF-16 text (which every XML reader must accept) as UTF-8, so one byte-based reader
    serves both; other bytes unchanged. UnicodeDecodeError when it does not decode. Without
    a byte-order mark, UTF-16 is known by its first character: one a document may begin with."""
    if data[:4] in (codecs.BOM_UTF32_LE, codecs.BOM_UTF32_BE):
        raise UnicodeDecodeError("utf-32", data, 0, 4, "UTF-32 is not read, only UTF-8 and UTF-16")
    if data[:2] in (codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE):
        encoding = "utf-16"
    elif data[:2] in _UTF16_LE_STARTS:
        encoding = "utf-16-le"
    elif data[:2] in _UTF16_BE_STARTS:
        encoding = "utf-16-be"
    else:
        return data
    text = _DECLARED_ENCODING.sub(r"\1\2UTF-8\2", data.decode(encoding), count=1)
    return text.encode("utf-8")


def _parser_limit(message: str, loc: Location) -> Diagnostic | None:
    """One of libxml2's fixed limits, said in our words; None for any other syntax error."""
    for words, what, hint in _PARSER_LIMITS:
        if any(w in message for w in words):
            return error("ATD007", what, loc, hint)
    return None


def parse_bytes(data: bytes, file: str) -> tuple[ParsedXml | None, list[Diagnostic]]:
    """Parse untrusted bytes; on refusal return None and the one reason why."""
    if len(data) > MAX_BYTES:
        return None, [_too_big(len(data), file)]
    try:
        data = _utf16_as_utf8(data)
    except UnicodeDecodeError as exc:
        return None, [error("ATD006", f"cannot decode file as {exc.encoding.upper()}: {exc.reason}", Location(file, 1, 1),
                            "save the file as UTF-8")]
    if b"\x00" in data[:65536] or not data.strip():
        what = "is empty" if not data.strip() else "is binary, not XML text"
        return None, [error("ATD006", f"file {what}", Location(file, 1, 1), "an ATD is an XML text file")]
    doctype = _DOCTYPE.search(data)
    if doctype:
        line, col = _line_col(data, doctype.start())
        return None, [
            error(
                "ATD004",
                "DOCTYPE and entity declarations are not allowed in an ATD",
                Location(file, line, col),
                "remove the <!DOCTYPE ...> block; ATD files need no DTD or entities",
            )
        ]
    try:
        root = etree.fromstring(data, _parser())
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (1, 1)
        message = str(exc.msg or exc).split(", line ")[0].strip()
        if "Excessive depth" in message:
            return None, [
                error("ATD005", "elements are nested too deeply", Location(file, line, col),
                      f"an ATD nests 4 levels (statemachine, state, path, position); this file nests over {MAX_DEPTH}")
            ]
        limit = _parser_limit(message, Location(file, line, max(col, 1)))
        if limit:
            return None, [limit]
        return None, [
            error("ATD003", f"not well-formed XML: {message}", Location(file, line, max(col, 1)),
                  "check the tag at this place is closed and the file is complete")
        ]
    except ValueError as exc:  # e.g. undecodable text in the declared encoding
        return None, [error("ATD006", f"cannot decode file: {exc}", Location(file, 1, 1),
                            "save the file as UTF-8")]
    return ParsedXml(root, file, _tag_starts(data, root, file)), []


def read_file(path: Path, shown_as: str | None = None) -> tuple[ParsedXml | None, list[Diagnostic]]:
    """Read and parse a file through the input guard: a regular file, never more than MAX_BYTES."""
    file = shown_as or str(path)
    try:
        data = read_capped(Path(path), MAX_BYTES)
    except InputTooBig:
        return None, [_too_big(_reported_size(path), file)]
    except InputError as exc:
        return None, [error("ATD001", str(exc), Location(file, 0, 0), _INPUT_HINT)]
    return parse_bytes(data, file)


_INPUT_HINT = "name an ATD file (a regular .xml file)"


def _reported_size(path: Path) -> int:
    try:
        return max(Path(path).stat().st_size, MAX_BYTES + 1)
    except OSError:
        return MAX_BYTES + 1
