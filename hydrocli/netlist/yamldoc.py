"""YAML documents with line/column information and comment-preserving round trips.

ruamel.yaml's round-trip loader builds plain data (no arbitrary objects: it is safe) while
keeping where every key and value sits, and writes a document back with its comments.
"""
from __future__ import annotations

import io
import os
import tempfile
from pathlib import Path

from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap, CommentedSeq
from ruamel.yaml.error import MarkedYAMLError

from ..errors import Location, NetlistError, Problem


def _yaml() -> YAML:
    y = YAML(typ="rt")
    y.preserve_quotes = True
    y.width = 120
    y.indent(mapping=2, sequence=4, offset=2)
    return y


def load_text(text: str, file: str) -> CommentedMap:
    """Parse YAML text; syntax errors become a located NetlistError."""
    try:
        doc = _yaml().load(text)
    except MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        loc = Location(file, mark.line + 1 if mark else None, mark.column + 1 if mark else None)
        msg = (exc.problem or exc.context or "malformed YAML").strip()
        raise NetlistError(Problem(f"malformed YAML: {msg}", loc,
                                   "check indentation, colons after keys and matching quotes/brackets")) from None
    except Exception as exc:  # duplicate keys and other constructor errors
        text_exc = str(exc).strip().splitlines()
        line = None
        for ln in text_exc:
            if "line" in ln:
                import re
                m = re.search(r"line (\d+), column (\d+)", ln)
                if m:
                    line = (int(m.group(1)), int(m.group(2)))
        loc = Location(file, line[0] if line else None, line[1] if line else None)
        first = text_exc[0] if text_exc else exc.__class__.__name__
        raise NetlistError(Problem(f"malformed YAML: {first}", loc, "each key may appear once per mapping")) from None
    if doc is None:
        doc = CommentedMap()
    if not isinstance(doc, CommentedMap):
        raise NetlistError(Problem("the file must be a YAML mapping (key: value lines) at the top level",
                                   Location(file, 1, 1)))
    return doc


def load_file(path: str | Path) -> tuple[CommentedMap, str]:
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise NetlistError(Problem(f"file not found: {p}", Location(str(p)), "check the path")) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise NetlistError(Problem(f"cannot read {p}: {exc}", Location(str(p)))) from None
    return load_text(text, str(p)), text


def dump_text(doc) -> str:
    buf = io.StringIO()
    _yaml().dump(doc, buf)
    return buf.getvalue()


def write_atomic(path: str | Path, text: str) -> None:
    """Write text to ``path`` through a temporary file and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=str(path.parent))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def key_loc(m, key, file: str, ypath: str = "") -> Location:
    """Location of ``key`` in mapping ``m`` (1-based)."""
    try:
        line, col = m.lc.key(key)
        return Location(file, line + 1, col + 1, ypath or None)
    except Exception:
        return node_loc(m, file, ypath)


def value_loc(m, key, file: str, ypath: str = "") -> Location:
    try:
        line, col = m.lc.value(key)
        return Location(file, line + 1, col + 1, ypath or None)
    except Exception:
        return key_loc(m, key, file, ypath)


def item_loc(seq, i: int, file: str, ypath: str = "") -> Location:
    try:
        line, col = seq.lc.item(i)
        return Location(file, line + 1, col + 1, ypath or None)
    except Exception:
        return node_loc(seq, file, ypath)


def node_loc(node, file: str, ypath: str = "") -> Location:
    try:
        return Location(file, node.lc.line + 1, node.lc.col + 1, ypath or None)
    except Exception:
        return Location(file, None, None, ypath or None)


def is_map(x) -> bool:
    return isinstance(x, (CommentedMap, dict))


def is_seq(x) -> bool:
    return isinstance(x, (CommentedSeq, list))
