# SPDX-License-Identifier: Apache-2.0
"""Every repository path the documents name exists, and every local link resolves.

Read: README.md and docs/*.md (the whole text), the comments of the Verilog files (rtl/*.v,
sim/vectors/*.v, tests/mutants/*.v) and the docstrings and comments of the Python files
(model/, sim/, tests/, scripts/).  Three checks:

* a path token, a word starting with ``model/``, ``rtl/``, ``sim/``, ``tests/``, ``docs/`` or
  ``scripts/`` and ending in an extension (``model/units/fixed.py``) or a slash
  (``model/units/``), names a file or folder of the checkout, relative to its root.  A
  token with a placeholder or a wildcard (``sim/vectors/tb_<unit>.v``, ``rtl/rom/*.hex``) is
  checked up to the last folder before it;
* a bare document name in capitals (``README.md``) is a file at the root of the checkout or
  under docs/;
* a markdown link or image to a local file (``[text](docs/divider.md)``, relative to the page
  that holds it) resolves, and its ``#anchor``, when it points into a markdown page, is one of
  that page's headings.

A failure lists every miss as ``file:line: what``.
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PREFIXES = ("model", "rtl", "sim", "tests", "docs", "scripts")
# A path token: one of the prefixes at a word start (not inside a longer path or a URL).
PATH = re.compile(rf"(?<![\w./~-])(?:{'|'.join(PREFIXES)})/[\w./<>{{}}*-]*")
BARE_DOC = re.compile(r"(?<![\w./-])([A-Z][A-Z0-9_-]*\.md)\b")
LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
EXTERNAL = re.compile(r"^(?:[a-z][a-z0-9+.-]*:|//)", re.I)


# ------------------------------------------------------------------ what the documents say
def markdown_files() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def verilog_files() -> list[Path]:
    return [
        *sorted((ROOT / "rtl").glob("*.v")),
        *sorted((ROOT / "sim" / "vectors").glob("*.v*")),
        *sorted((ROOT / "tests" / "mutants").glob("*.v")),
    ]


def python_files() -> list[Path]:
    return [
        p for folder in ("model", "sim", "tests", "scripts") for p in (ROOT / folder).rglob("*.py")
    ]


def verilog_comments(text: str) -> list[tuple[int, str]]:
    """(line, text) of every ``//`` and ``/* */`` comment (string literals skipped)."""
    found = []
    for m in re.finditer(r'"(?:\\.|[^"\\])*"|//[^\n]*|/\*.*?\*/', text, re.S):
        if not m.group(0).startswith('"'):
            found.append((text.count("\n", 0, m.start()) + 1, m.group(0)))
    return found


def is_string(stmt: ast.stmt | None) -> bool:
    """A statement that is a lone string (a docstring)."""
    return (
        isinstance(stmt, ast.Expr)
        and isinstance(stmt.value, ast.Constant)
        and isinstance(stmt.value.value, str)
    )


def python_prose(text: str) -> list[tuple[int, str]]:
    """(line, text) of every docstring (module, class, function) and every comment."""
    found = []
    tree = ast.parse(text)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            first = node.body[0] if node.body else None
            if is_string(first):
                found.append((first.lineno, first.value.value))
        # A string expression standing alone after an assignment documents it too.
        if isinstance(node, (ast.Module, ast.ClassDef)):
            found += [(stmt.lineno, stmt.value.value) for stmt in node.body[1:] if is_string(stmt)]
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type == tokenize.COMMENT:
            found.append((tok.start[0], tok.string))
    return found


def prose() -> list[tuple[Path, int, str]]:
    """(file, first line, text) of every piece of prose the check reads."""
    pieces = [(p, 1, p.read_text()) for p in markdown_files()]
    for p in verilog_files():
        pieces += [(p, line, t) for line, t in verilog_comments(p.read_text())]
    for p in python_files():
        pieces += [(p, line, t) for line, t in python_prose(p.read_text())]
    return pieces


def where(path: Path, first_line: int, text: str, offset: int) -> str:
    return f"{path.relative_to(ROOT)}:{first_line + text.count(chr(10), 0, offset)}"


# ------------------------------------------------------------------ the checks
def path_to_check(token: str) -> str | None:
    """The part of a path token that must exist, or None when the token names no path."""
    token = token.rstrip(".,;:")
    for i, ch in enumerate(token):
        if ch in "<>{}*":  # a placeholder or a wildcard: check the folder it sits in
            return token[: token.rfind("/", 0, i) + 1]
    if token.endswith("/"):
        return token
    if re.search(r"\.[A-Za-z0-9]+$", token.rsplit("/", 1)[-1]):
        return token
    return None


def missing_paths() -> list[str]:
    missing = []
    for path, line, text in prose():
        for m in PATH.finditer(text):
            target = path_to_check(m.group(0))
            if target and not (ROOT / target).exists():
                missing.append(f"{where(path, line, text, m.start())}: {target} does not exist")
    return sorted(set(missing))


def missing_bare_docs() -> list[str]:
    missing = []
    for path, line, text in prose():
        for m in BARE_DOC.finditer(text):
            name = m.group(1)
            if not (ROOT / name).is_file() and not (ROOT / "docs" / name).is_file():
                missing.append(
                    f"{where(path, line, text, m.start())}: {name} is not in the repository"
                )
    return sorted(set(missing))


def slug(heading: str) -> str:
    """GitHub's anchor of a markdown heading."""
    text = re.sub(r"[`*_]|\[([^\]]*)\]\([^)]*\)", r"\1", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(page: Path) -> set[str]:
    text = re.sub(r"^```.*?^```", "", page.read_text(), flags=re.S | re.M)
    seen: dict[str, int] = {}
    found = set()
    for m in re.finditer(r"^#{1,6}\s+(.*?)\s*#*\s*$", text, re.M):
        base = slug(m.group(1))
        n = seen.get(base, 0)
        seen[base] = n + 1
        found.add(base if n == 0 else f"{base}-{n}")
    return found


def broken_links() -> list[str]:
    broken = []
    for page in markdown_files():
        text = page.read_text()
        # Links inside fenced code blocks are examples, not links.
        masked = re.sub(r"^```.*?^```", lambda m: " " * len(m.group(0)), text, flags=re.S | re.M)
        for m in LINK.finditer(masked):
            target = m.group(1)
            if EXTERNAL.match(target):
                continue
            file_part, _, anchor = target.partition("#")
            resolved = (page.parent / file_part).resolve() if file_part else page
            at = where(page, 1, text, m.start())
            if not resolved.exists():
                broken.append(f"{at}: link ({target}) leads nowhere: {file_part} does not exist")
            elif anchor and resolved.suffix == ".md" and anchor not in anchors(resolved):
                broken.append(
                    f"{at}: link ({target}): no heading #{anchor} in {file_part or page.name}"
                )
    return broken


def report(kind: str, misses: list[str]) -> str:
    return f"{len(misses)} {kind}:\n" + "\n".join(misses)


def test_every_named_path_exists() -> None:
    misses = missing_paths()
    assert not misses, report("paths named in the documents that do not exist", misses)


def test_every_named_document_is_in_the_repository() -> None:
    misses = missing_bare_docs()
    assert not misses, report("documents cited that the repository does not hold", misses)


def test_every_local_link_resolves() -> None:
    misses = broken_links()
    assert not misses, report("broken local links", misses)


# ------------------------------------------------------------------ the check itself
def test_the_check_finds_what_it_should() -> None:
    text = (
        "see `model/units/fixed.py`, model/no_such.py, rtl/rom/*.hex, sim/vectors/tb_<unit>.v, "
        "https://example.org/model/x.py, model.units.fixed, the model/units/ folder, docs/."
    )
    tokens = [path_to_check(m.group(0)) for m in PATH.finditer(text)]
    assert tokens == [
        "model/units/fixed.py",
        "model/no_such.py",
        "rtl/rom/",
        "sim/vectors/",
        "model/units/",
        "docs/",
    ]
    assert path_to_check("tests/test_contract_") is None  # a name being built, not a path
    comments = verilog_comments('// rtl/a.v\nparameter F = "rom/x.hex"; /* docs/b.md\n*/\n')
    assert comments == [(1, "// rtl/a.v"), (2, "/* docs/b.md\n*/")]
    prose_ = python_prose('"""Doc: sim/x.py."""\nx = "model/y.py"  # tests/z.py\n')
    assert [t for _, t in prose_] == ["Doc: sim/x.py.", "# tests/z.py"]
    assert slug("Timing (`busy`, `valid`)") == "timing-busy-valid"
    assert slug("Contract: every sentence and its test") == "contract-every-sentence-and-its-test"
    found = [m.group(1) for m in LINK.finditer("[a](docs/x.md#y) ![p](docs/p.png) [u](https://x)")]
    assert found == ["docs/x.md#y", "docs/p.png", "https://x"]
