"""soadyn's own model files: save_model / load_model, and pickling of a Model.

The format (JSON, "format": "soadyn-model", "version": 1) is written and read
by the C++ library (soadyn/model/model_file.hpp: `soadyn::save_model`,
`soadyn::load_model`), so a model built in Python loads unchanged in a C++
simulator or a campaign worker. Numbers are written with the 17 significant
digits that round-trip: a loaded model's dynamics equal the saved model's bit
for bit. The model-file guide (docs/guides/model-files.md) describes every key.

What the dynamics do not use travels in the file's "description" object,
which the C++ reader keeps without reading it:
- "visuals": the model's `soadyn.Visual` list (mesh vertices and faces included);
- "metadata": a JSON object of the caller's (e.g. the scene's name and source).

Bounds (bounded_input.py): a text larger than MAX_INPUT_BYTES or nested
deeper than MAX_NESTING_DEPTH is refused before any parser sees it, here
as well as by the C++ reader, so a hostile file is a ModelFileError at any
depth, never a RecursionError or a stack overflow; a model whose metadata
would make such a file is refused when saved.
"""
from __future__ import annotations

import copyreg
import json
import os
from typing import Optional

from .._soadyn import ModelFileError
from ..bounded_input import MAX_NESTING_DEPTH, check_json, check_size, json_depth, read_text
from ..model import Model
from ..viz.visuals import Visual
from .text_files import write_text

__all__ = ["save_model", "load_model", "model_to_json", "model_from_json", "ModelFileError"]

_VISUAL_ARRAYS = ("size", "rotation", "translation", "rgba", "vertices", "faces")


def _visual_to_dict(v: Visual) -> dict:
    d = {"name": v.name, "frame": v.frame, "shape": v.shape}
    for key in _VISUAL_ARRAYS:
        value = getattr(v, key)
        if value is not None:
            d[key] = value.tolist()
    if v.mesh_file is not None:
        d["mesh_file"] = v.mesh_file
    return d


def _visual_from_dict(d, where: str) -> Visual:
    if not isinstance(d, dict):
        raise ModelFileError(f"{where}: a visual must be an object, got {type(d).__name__}")
    known = {"name", "frame", "shape", "mesh_file", *_VISUAL_ARRAYS}
    unknown = sorted(set(d) - known)
    if unknown:
        raise ModelFileError(f"{where}: unknown key '{unknown[0]}' (known: {', '.join(sorted(known))})")
    for key in ("name", "frame", "shape"):
        if not isinstance(d.get(key), str):
            raise ModelFileError(f"{where}/{key}: a string is required")
    try:
        return Visual(**d)
    except (TypeError, ValueError) as exc:
        raise ModelFileError(f"{where}: {exc}") from exc


def _description_text(m: Model, metadata: Optional[dict]) -> str:
    description = {}
    if m.visuals:
        description["visuals"] = [_visual_to_dict(v) for v in m.visuals]
    if metadata is None:
        metadata = _stored_metadata(m)
    if metadata:
        description["metadata"] = metadata
    try:
        text = json.dumps(description, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise ModelFileError(f"metadata must be JSON data (finite numbers, strings, lists, objects): {exc}") \
            from exc
    except RecursionError:
        raise ModelFileError(f"metadata nested more than the {MAX_NESTING_DEPTH} levels a model file may hold "
                             f"(soadyn.bounded_input.MAX_NESTING_DEPTH)") from None
    depth = json_depth(text) + 1  # the description is an object inside the file's
    if depth > MAX_NESTING_DEPTH:
        raise ModelFileError(f"metadata would nest the model file {depth} levels deep, more than the "
                             f"{MAX_NESTING_DEPTH} levels a reader accepts (soadyn.bounded_input.MAX_NESTING_DEPTH)")
    return text


def _stored_metadata(m: Model) -> dict:
    try:
        stored = json.loads(m._description)
    except ValueError:
        return {}
    metadata = stored.get("metadata") if isinstance(stored, dict) else None
    return metadata if isinstance(metadata, dict) else {}


def _restore_description(m: Model, source: str) -> None:
    """Visuals back onto the model from the description the C++ reader kept."""
    try:
        description = json.loads(m._description)
    except (ValueError, RecursionError) as exc:  # checked JSON within the bounds already; defensive
        raise ModelFileError(f"{source}: /description: {exc}") from exc
    if not isinstance(description, dict):
        raise ModelFileError(f"{source}: /description must be an object")
    unknown = sorted(set(description) - {"visuals", "metadata"})
    if unknown:
        raise ModelFileError(f"{source}: /description: unknown key '{unknown[0]}' (known: metadata, visuals)")
    visuals = description.get("visuals", [])
    if not isinstance(visuals, list):
        raise ModelFileError(f"{source}: /description/visuals must be a list")
    if not isinstance(description.get("metadata", {}), dict):
        raise ModelFileError(f"{source}: /description/metadata must be an object")
    m.visuals = [_visual_from_dict(v, f"{source}: /description/visuals/{i}") for i, v in enumerate(visuals)]


def model_to_json(m: Model, metadata: Optional[dict] = None) -> str:
    """The model-file text of `m` (visuals and `metadata` included; metadata defaults to the loaded one's)."""
    if not isinstance(m, Model):
        raise TypeError(f"model_to_json needs a soadyn.Model, got {type(m).__name__}")
    previous = m._description
    m._description = _description_text(m, metadata)
    try:
        text = m._to_json()
    finally:
        m._description = previous
    check_size(len(text.encode("utf-8")), "the model-file text", ModelFileError)
    return text


def model_from_json(text: str, source: str = "model JSON") -> Model:
    """The model a model-file text holds; ModelFileError names `source` and the item at fault."""
    if not isinstance(text, str):
        raise TypeError(f"model_from_json needs the JSON text as str, got {type(text).__name__}")
    check_json(text, source, ModelFileError)
    m = Model()
    m._load_json(text, source)
    _restore_description(m, source)
    return m


def save_model(m: Model, path, metadata: Optional[dict] = None) -> None:
    """Write `m` to `path` in soadyn's model-file format (JSON; the model-file reference page describes it).

    metadata: a JSON-serialisable dict kept in the file's description (None: the loaded model's). Raises
    TypeError for a non-Model, ModelFileError naming the path for metadata that is not JSON or too deeply nested
    and for a path that cannot be written (a missing directory, no permission), with the reason.
    """
    try:
        text = model_to_json(m, metadata)
    except ModelFileError as exc:
        raise ModelFileError(f"{os.fspath(path)}: cannot save the model: {exc}") from exc
    write_text(path, text, ModelFileError, "model file")


def load_model(path) -> Model:
    """The model stored at `path` by save_model (or by soadyn::save_model in C++).

    Raises ModelFileError naming the path and the JSON path of the item at fault (/bodies/3/mass) for a missing
    or unreadable file, invalid JSON, a newer version, a missing, mistyped, non-finite or unknown value, and a
    file over the size or nesting limit (the model-file reference page).
    """
    path = os.fspath(path)
    return model_from_json(read_text(path, path, ModelFileError, "model file"), path)


def metadata(m: Model) -> dict:
    """The metadata a loaded model file carried (an empty dict when none)."""
    return _stored_metadata(m)


def _unpickle(text: str) -> Model:
    return model_from_json(text, "pickled soadyn.Model")


def reduce_model(m: Model):
    """How a Model pickles: as its model-file text (visuals and metadata included), never as pointers."""
    return (_unpickle, (model_to_json(m),))


# Registered here, beside the format, rather than as Model.__reduce__, so that model.py need not import the
# format that imports it; pickle looks the Model type up in copyreg's table.
copyreg.pickle(Model, reduce_model)

