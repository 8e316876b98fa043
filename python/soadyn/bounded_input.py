"""Bounds on the files soadyn reads from outside: their size and how deeply they nest.

Every reader of files that may come from anyone (model files, URDF, MJCF)
refuses, with its own error naming the file and the limit:
- a file larger than MAX_INPUT_BYTES (512 MiB), before reading it;
- JSON or XML nested more than MAX_NESTING_DEPTH (256) levels.

Nesting is counted from the outermost container: a JSON file's top-level
object is level 1 (`{"a": [1]}` is 2 levels deep), an XML file's root
element is level 1. No file soadyn writes comes near either limit (a model
file nests at most 8 levels plus its metadata, a URDF 5); the limits keep hostile
files from exhausting the stack of a recursive parser (Python's json and
tomllib recurse, and so does serialising a parsed document) or the memory.
tests/io/test_model_file.py holds the C++ model-file reader (what C++ programs
and campaign workers call) to the same depth, counted the same way.

The JSON depth is found before any parser sees the text, by a vectorised
scan (numpy) of the brackets outside strings, a few per cent of the time
parsing the same text takes. XML is parsed by expat (iterative) into
ElementTree with a tree builder that stops at the first element too deep,
so a deep file never becomes a deep tree.
"""
from __future__ import annotations

import os
import re
from xml.etree import ElementTree

import numpy as np

__all__ = ["MAX_NESTING_DEPTH", "MAX_INPUT_BYTES", "check_size", "read_bytes", "read_text", "json_depth",
           "check_json", "parse_xml"]

MAX_NESTING_DEPTH = 256
MAX_INPUT_BYTES = 512 * 1024 * 1024

# The JSON scan keeps the structural bytes, the quotes and what may follow a backslash in a string.
_JSON_KEPT = b'[]{}"\\/bfnrtu'
_JSON_DROPPED = bytes(c for c in range(256) if c not in _JSON_KEPT)
_JSON_ESCAPE = re.compile(rb"\\.", re.DOTALL)


def check_size(nbytes: int, label: str, error: type) -> None:
    """`error` naming `label` when `nbytes` is beyond MAX_INPUT_BYTES."""
    if nbytes > MAX_INPUT_BYTES:
        raise error(f"{label}: {nbytes} bytes, more than the {MAX_INPUT_BYTES} bytes (512 MiB) soadyn reads "
                    f"from one file (soadyn.bounded_input.MAX_INPUT_BYTES)")


def read_bytes(path, label: str, error: type, what: str) -> bytes:
    """The bytes of the file at `path`, at most MAX_INPUT_BYTES of them (a file that says it is larger, or
    turns out larger while read, is refused); `error` names `label` and `what` was being read."""
    try:
        with open(os.fspath(path), "rb") as f:
            check_size(os.fstat(f.fileno()).st_size, label, error)
            data = f.read(MAX_INPUT_BYTES + 1)
    except OSError as exc:
        raise error(f"{label}: cannot read the {what}: {exc.strerror or exc}") from exc
    check_size(len(data), label, error)
    return data


def read_text(path, label: str, error: type, what: str) -> str:
    """read_bytes decoded as UTF-8; text that is not UTF-8 is refused the same way."""
    try:
        return read_bytes(path, label, error, what).decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{label}: cannot read the {what}: {exc}") from exc


def json_depth(text: str) -> int:
    """How many levels of arrays and objects `text` nests (0 for a bare value), counted without parsing.

    Brackets inside strings do not count: string bounds are the quotes left once every backslash escape
    is removed. Past a syntax error a parser stops while this scan goes on, so the result bounds what any
    parser reaches."""
    kept = text.encode("utf-8", "surrogatepass").translate(None, _JSON_DROPPED)
    if b"\\" in kept:
        kept = _JSON_ESCAPE.sub(b"", kept)
    kept = kept.translate(None, b"/bfnrtu")
    data = np.frombuffer(kept, dtype=np.uint8)
    inside_string = np.bitwise_xor.accumulate((data == ord('"')).view(np.uint8)).view(bool)
    step = np.zeros(data.size, dtype=np.int8)
    step[(data == ord("[")) | (data == ord("{"))] = 1
    step[(data == ord("]")) | (data == ord("}"))] = -1
    step[inside_string] = 0
    return int(np.cumsum(step, dtype=np.int64).max(initial=0))


def check_json(text: str, label: str, error: type) -> None:
    """`error` naming `label` when the JSON `text` is larger than MAX_INPUT_BYTES or nests deeper than
    MAX_NESTING_DEPTH."""
    check_size(len(text.encode("utf-8", "surrogatepass")), label, error)
    depth = json_depth(text)
    if depth > MAX_NESTING_DEPTH:
        raise error(f"{label}: JSON nested {depth} levels deep, more than the {MAX_NESTING_DEPTH} levels soadyn "
                    f"reads (soadyn.bounded_input.MAX_NESTING_DEPTH)")


class _BoundedTreeBuilder(ElementTree.TreeBuilder):
    """An ElementTree builder that refuses an element nested deeper than MAX_NESTING_DEPTH."""

    def __init__(self, label: str, error: type):
        super().__init__()
        self.label, self.error, self.depth = label, error, 0

    def start(self, tag, attributes):
        self.depth += 1
        if self.depth > MAX_NESTING_DEPTH:
            raise self.error(f"{self.label}: <{tag}> is nested more than {MAX_NESTING_DEPTH} elements deep, "
                             f"the most soadyn reads (soadyn.bounded_input.MAX_NESTING_DEPTH)")
        return super().start(tag, attributes)

    def end(self, tag):
        self.depth -= 1
        return super().end(tag)


def parse_xml(data, label: str, error: type) -> ElementTree.Element:
    """The root element of the XML document `data` (bytes or str); `error` naming `label` when it is larger
    than MAX_INPUT_BYTES or nests deeper than MAX_NESTING_DEPTH; ElementTree.ParseError when it is not
    well-formed."""
    check_size(len(data.encode("utf-8", "surrogatepass")) if isinstance(data, str) else len(data), label, error)
    parser = ElementTree.XMLParser(target=_BoundedTreeBuilder(label, error))
    parser.feed(data)
    return parser.close()
