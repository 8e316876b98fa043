"""The bounds on untrusted files (soadyn.bounded_input): size and nesting depth.

The JSON depth scan counts the brackets a parser would nest, strings and
escapes included, without parsing; the bounded XML parser stops at the first
element too deep; every reader of files from outside (model files, URDF,
MJCF) refuses a file over the size limit before reading it, naming the file
and the limit.
"""
from __future__ import annotations

import json
from xml.etree import ElementTree

import pytest

import soadyn
from soadyn.bounded_input import MAX_INPUT_BYTES, MAX_NESTING_DEPTH, json_depth, parse_xml, read_bytes

DEPTHS = {
    "1": 0, '"[{"': 0, "[]": 1, "{}": 1, '{"a": [1, {"b": []}]}': 4, "[[[]], [[[]]]]": 4,
    '["]]]"]': 1, '["[[["]': 1, r'["\"[[["]': 1, r'["\\", [[]]]': 3, r'["\\\"[", []]': 2,
    r'{"a\u005b": "\n{", "b": [[]]}': 3, '{"\u00e9": ["\u2603["]}': 2, r'["\/", "\b\f\r\t", []]': 2,
}


@pytest.mark.parametrize("text", sorted(DEPTHS))
def test_json_depth_counts_what_a_parser_nests(text):
    assert json_depth(text) == DEPTHS[text]
    nested = json.loads(text)  # the reference: Python's parser, counting levels itself
    depth, stack = 0, [(nested, 1)]
    while stack:
        node, level = stack.pop()
        if isinstance(node, (list, dict)):
            depth = max(depth, level)
            stack.extend((x, level + 1) for x in (node.values() if isinstance(node, dict) else node))
    assert json_depth(text) == depth


def test_json_depth_of_a_huge_nesting():
    assert json_depth("[" * 300_000 + "]" * 300_000) == 300_000
    assert json_depth('{"a":' * 1000 + "1" + "}" * 1000) == 1000


def test_xml_nesting_is_bounded_at_the_limit():
    deepest = "<a>" * MAX_NESTING_DEPTH + "</a>" * MAX_NESTING_DEPTH
    root = parse_xml(deepest, "test XML", ValueError)
    assert root.tag == "a"
    for too_deep in (MAX_NESTING_DEPTH + 1, 100_000):
        with pytest.raises(ValueError, match=rf"test XML: <a> is nested more than {MAX_NESTING_DEPTH} elements deep"):
            parse_xml("<a>" * too_deep + "</a>" * too_deep, "test XML", ValueError)
    with pytest.raises(ElementTree.ParseError):
        parse_xml(b"<a><b></a>", "test XML", ValueError)


def sparse_file(path, size: int):
    """A file of `size` bytes that takes no room on disk."""
    with open(path, "wb") as f:
        f.truncate(size)
    return path


def test_read_bytes_refuses_a_file_over_the_limit_unread(tmp_path):
    path = sparse_file(tmp_path / "huge.bin", MAX_INPUT_BYTES + 1)
    with pytest.raises(ValueError, match=rf"huge.bin: {MAX_INPUT_BYTES + 1} bytes, more than the {MAX_INPUT_BYTES}"):
        read_bytes(path, str(path), ValueError, "file")
    with pytest.raises(ValueError, match="missing.bin: cannot read the file"):
        read_bytes(tmp_path / "missing.bin", str(tmp_path / "missing.bin"), ValueError, "file")


LOADERS = {"model file": (soadyn.load_model, soadyn.ModelFileError, "model.json"),
           "URDF": (soadyn.load_urdf, soadyn.UrdfError, "robot.urdf"),
           "MJCF": (soadyn.load_mjcf, soadyn.MjcfError, "model.xml")}


@pytest.mark.parametrize("reader", sorted(LOADERS))
def test_every_reader_refuses_a_file_over_the_size_limit(reader, tmp_path):
    load, error, name = LOADERS[reader]
    path = sparse_file(tmp_path / name, MAX_INPUT_BYTES + 1)
    with pytest.raises(error) as refused:
        load(path)
    assert str(path) in str(refused.value) and "MAX_INPUT_BYTES" in str(refused.value)
