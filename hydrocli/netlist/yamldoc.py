"""YAML documents with line/column information and comment-preserving round trips.

ruamel.yaml's round-trip loader builds plain data (no arbitrary objects: it is safe) while
keeping where every key and value sits, and writes a document back with its comments.
"""
from __future__ import annotations

import io
import re
from pathlib import Path

from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap, CommentedSeq, TaggedScalar
from ruamel.yaml.constructor import DuplicateKeyError
from ruamel.yaml.error import MarkedYAMLError

from ..errors import Location, NetlistError, Problem

#: Limits of the safe loader: a hostile or careless file is refused in well under a second
#: instead of hanging ("billion laughs" alias bombs, megabyte files, absurd nesting).
MAX_BYTES = 1_000_000          # a machine or experiment file is a few kB
MAX_NODES = 200_000            # values visited with aliases expanded (each alias counts again)
MAX_DEPTH = 50                 # nesting of mappings/lists
MAX_ALIASES = 1_000            # '*name' references in one file


def _yaml() -> YAML:
    y = YAML(typ="rt")
    y.preserve_quotes = True
    y.width = 120
    y.indent(mapping=2, sequence=4, offset=2)
    return y


def load_text(text: str, file: str) -> CommentedMap:
    """Parse YAML text safely (plain data only); syntax errors, duplicate keys and YAML tags
    become located NetlistErrors."""
    _check_text(text, file)
    try:
        doc = _yaml().load(text)
    except RecursionError:
        raise NetlistError(Problem(f"the YAML is nested too deeply (more than {MAX_DEPTH} levels)",
                                   Location(file, 1, 1), "flatten the file")) from None
    except DuplicateKeyError as exc:
        raise NetlistError(_duplicate_problem(exc, file)) from None
    except MarkedYAMLError as exc:
        raise NetlistError(_syntax_problem(exc, file, text)) from None
    except Exception as exc:  # other constructor errors: never a traceback
        raise NetlistError(Problem(f"malformed YAML: {str(exc).strip().splitlines()[0] if str(exc).strip() else exc}",
                                   Location(file, 1, 1), "check the YAML syntax")) from None
    if doc is None:
        doc = CommentedMap()
    if not isinstance(doc, CommentedMap):
        raise NetlistError(Problem(f"the file must be a YAML mapping (key: value lines) at the top level, "
                                   f"not a {kind(doc)}", Location(file, 1, 1),
                                   "start with keys such as 'name:', 'components:', 'inputs:'"))
    _check_expansion(doc, file)
    tagged = list(_tagged(doc, file, ""))
    if tagged:
        raise NetlistError(tagged)
    return doc


def _check_text(text: str, file: str) -> None:
    """Refuse files too large to be a machine or experiment, or with too many aliases,
    before parsing them (parsing megabytes of YAML takes minutes)."""
    if len(text) > MAX_BYTES:
        raise NetlistError(Problem(f"the file is {len(text) / 1e6:.1f} MB; a machine or experiment file is "
                                   f"limited to {MAX_BYTES / 1e6:g} MB", Location(file, 1, 1),
                                   "put recorded data in a CSV/HDF5 file and use templates for repeated circuits"))
    depth = 0
    for m in re.finditer(r"[\[\]{}]", text):
        depth = depth + 1 if m.group() in "[{" else max(depth - 1, 0)
        if depth > MAX_DEPTH:
            line = text.count("\n", 0, m.start()) + 1
            raise NetlistError(Problem(f"the YAML is nested more than {MAX_DEPTH} levels deep",
                                       Location(file, line, m.start() - text.rfind("\n", 0, m.start())),
                                       "flatten the file"))
    n_alias = len(re.findall(r"(?:^|[\s\[{,:])\*[^\s,\]}]+", text))
    if n_alias > MAX_ALIASES:
        raise NetlistError(Problem(f"the file uses {n_alias} YAML aliases ('*name'); at most {MAX_ALIASES} are allowed",
                                   Location(file, 1, 1), "use templates or includes instead of many aliases"))


def _check_expansion(doc, file: str) -> None:
    """Walk the parsed document the way every later stage will, counting each aliased value
    again: refuse alias bombs (exponential expansion), self-referencing aliases and deep
    nesting with a located message."""
    count = 0
    stack = [(doc, 0, "", ())]
    while stack:
        node, depth, ypath, chain = stack.pop()
        count += 1
        if count > MAX_NODES:
            raise NetlistError(Problem(f"the YAML expands to more than {MAX_NODES} values once its aliases "
                                       "('*name') are expanded (an alias bomb?)", _where(node, file, ypath),
                                       "use templates or includes instead of nested aliases"))
        if depth > MAX_DEPTH:
            raise NetlistError(Problem(f"the YAML is nested more than {MAX_DEPTH} levels deep",
                                       _where(node, file, ypath), "flatten the file"))
        if isinstance(node, CommentedMap):
            items = node.items()
        elif isinstance(node, CommentedSeq):
            items = enumerate(node)
        else:
            continue
        if id(node) in chain:
            raise NetlistError(Problem("a YAML alias refers to a value that contains it (a recursive alias)",
                                       _where(node, file, ypath), "remove the '*name' inside '&name'"))
        sub_chain = chain + (id(node),)
        for k, v in items:
            if isinstance(v, (CommentedMap, CommentedSeq)):
                stack.append((v, depth + 1, f"{ypath}.{k}" if ypath else str(k), sub_chain))
            else:
                count += 1


def _where(node, file: str, ypath: str) -> Location:
    parts = ypath.split(".")
    ypath = ".".join(parts[:4]) + (".…" if len(parts) > 4 else "")
    return node_loc(node, file, ypath) if isinstance(node, (CommentedMap, CommentedSeq)) else Location(file, 1, 1, ypath)


def _mark_loc(mark, file: str) -> Location:
    return Location(file, mark.line + 1, mark.column + 1) if mark else Location(file)


def _duplicate_problem(exc, file: str) -> Problem:
    key = re.search(r'duplicate key "([^"]*)"', str(exc.problem or ""))
    first = exc.context_mark
    where = f" (first at line {first.line + 1})" if first else ""
    name = f"'{key.group(1)}'" if key else "a key"
    return Problem(f"duplicate key: {name} appears twice in the same mapping{where}",
                   _mark_loc(exc.problem_mark, file), "each key may appear once per mapping: remove or rename one")


def _syntax_problem(exc, file: str, text: str) -> Problem:
    mark = exc.problem_mark or exc.context_mark
    msg = (exc.problem or exc.context or "malformed YAML").strip()
    if exc.context and exc.context_mark and exc.problem_mark and exc.context_mark.line != exc.problem_mark.line:
        msg += f" ({exc.context.strip()} at line {exc.context_mark.line + 1}, column {exc.context_mark.column + 1})"
    hint = "check indentation, colons after keys and matching quotes/brackets"
    if "\t" in msg or (mark and _line(text, mark.line).startswith("\t")):
        hint = "YAML indentation must use spaces, not tabs"
    return Problem(f"malformed YAML: {msg}", _mark_loc(mark, file), hint)


def _line(text: str, i: int) -> str:
    lines = text.splitlines()
    return lines[i] if 0 <= i < len(lines) else ""


def kind(x) -> str:
    if isinstance(x, (list, CommentedSeq)):
        return "list"
    return "single value" if x is not None else "empty document"


def _tagged(node, file: str, ypath: str):
    """Problems for YAML tags (``!foo``, ``!!python/...``): machine files hold plain data only."""
    items = node.items() if isinstance(node, CommentedMap) else enumerate(node) if isinstance(node, CommentedSeq) else ()
    for k, v in items:
        sub = f"{ypath}.{k}" if ypath else str(k)
        tag = getattr(v, "tag", None)
        tag = getattr(tag, "value", tag)
        if isinstance(v, TaggedScalar) or (isinstance(v, (CommentedMap, CommentedSeq)) and tag):
            loc = value_loc(node, k, file, sub) if isinstance(node, CommentedMap) else item_loc(node, k, file, sub)
            yield Problem(f"YAML tag '{tag}' is not allowed in a machine file", loc,
                          "write a plain number, string, list or mapping")
        elif isinstance(v, (CommentedMap, CommentedSeq)):
            yield from _tagged(v, file, sub)


def load_file(path: str | Path) -> tuple[CommentedMap, str]:
    from ..fileio import note_input
    p = Path(path)
    note_input(p)
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
    from ..fileio import write_text_atomic
    write_text_atomic(path, text)


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
