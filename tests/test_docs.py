"""The documentation stands alone: no pointers to files users do not have, no
broken relative links, and the examples in docs/ run."""

from __future__ import annotations

import dataclasses
import importlib
import re
from pathlib import Path
from urllib.parse import unquote

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = sorted([ROOT / "README.md", *DOCS.glob("*.md")])

# internal project notes that are not in the repository or the wheel (split so this file does not match)
_INTERNAL = re.compile("|".join([r"\.\./" + "shared", "shared/", "ERR" + "ATA", "STYLE" + r"\.md",
                                 "DESIGN" + r"\.md", r"\b[Dd]ig" + r"est\b"]))
_SCANNED = ["README.md", "pyproject.toml", "docs", "uio_ring", "notebooks", "tests", "benchmarks", "examples"]
_SUFFIXES = {".md", ".py", ".ipynb", ".yaml", ".yml", ".toml", ".json", ".txt", ".rst", ".cfg"}


def _project_files() -> list[Path]:
    out = []
    for name in _SCANNED:
        path = ROOT / name
        if path.is_file():
            out.append(path)
        elif path.is_dir():
            out += [p for p in path.rglob("*") if p.is_file() and p.suffix in _SUFFIXES
                    and "__pycache__" not in p.parts and ".ipynb_checkpoints" not in p.parts]
    return sorted(p for p in out if p != Path(__file__).resolve())


def test_no_references_to_internal_notes():
    hits = []
    for path in _project_files():
        for n, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if _INTERNAL.search(line):
                hits.append(f"{path.relative_to(ROOT)}:{n}: {line.strip()[:120]}")
    assert not hits, "point to docs/ instead of internal notes:\n" + "\n".join(hits)


# ------------------------------------------------------------------ links
_LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")
_HEADING = re.compile(r"^#{1,6}\s+(.*?)\s*#*\s*$")
_ANCHOR = re.compile(r"""<a\s+(?:id|name)=["']([^"']+)["']""")


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|\*", "", heading).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def _anchors(page: Path) -> set[str]:
    text = page.read_text(encoding="utf-8")
    text = re.sub(r"```.*?```", "", text, flags=re.S)  # no headings inside code blocks
    found: set[str] = set(_ANCHOR.findall(text))
    seen: dict[str, int] = {}
    for line in text.splitlines():
        m = _HEADING.match(line)
        if m:
            slug = _slug(m.group(1))
            k = seen.get(slug, 0)
            seen[slug] = k + 1
            found.add(slug if k == 0 else f"{slug}-{k}")
    return found


def _links(page: Path) -> list[str]:
    text = re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.S)
    return _LINK.findall(text)


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_relative_links_resolve(page):
    broken = []
    for target in _links(page):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto: — not checked offline
            continue
        path_part, _, fragment = target.partition("#")
        dest = (page.parent / unquote(path_part)).resolve() if path_part else page
        if not dest.exists():
            broken.append(f"{target}: no file {dest}")
            continue
        if fragment and dest.suffix == ".md" and fragment not in _anchors(dest):
            broken.append(f"{target}: no anchor #{fragment} in {dest.name}")
    assert not broken, f"{page.relative_to(ROOT)}: broken links\n" + "\n".join(broken)


def test_the_docs_folder_is_linked_from_the_readme():
    readme_links = {t.partition("#")[0] for t in _links(ROOT / "README.md")}
    for page in DOCS.glob("*.md"):
        assert f"docs/{page.name}" in readme_links, f"README does not link docs/{page.name}"


# ------------------------------------------------------------------ the examples in the pages run
def _blocks(lang: str) -> list[tuple[str, str]]:
    out = []
    for page in PAGES:
        for i, block in enumerate(re.findall(rf"```{lang}\n(.*?)```", page.read_text(encoding="utf-8"), re.S)):
            out.append((f"{page.name}[{i}]", block))
    return out


def _runnable(code: str) -> bool:
    """A complete example: it starts with an import and has no ``...`` placeholder (fragments are not run)."""
    return code.startswith(("import ", "from ")) and "..." not in code


_PYTHON = [(w, c) for w, c in _blocks("python") if _runnable(c)]


@pytest.mark.parametrize(("where", "code"), _PYTHON, ids=[w for w, _ in _PYTHON])
def test_python_blocks_run(where, code):
    exec(compile(code, where, "exec"), {"__name__": "__docs__"})


_YAML = [(w, b) for w, b in _blocks("yaml") if re.search(r"^system:", b, re.M)]


@pytest.mark.parametrize(("where", "text"), _YAML, ids=[w for w, _ in _YAML])
def test_yaml_blocks_are_valid_specs(where, text):
    from uio_ring.spec import load_spec_text

    spec = load_spec_text(text)
    assert spec.system.n_x > 0


def test_dotted_names_in_the_docs_exist():
    """Every ``uio_ring.x.y`` the pages name can be imported (modules) or looked up (attributes)."""
    missing = []
    for page in PAGES:
        for name in sorted(set(re.findall(r"\buio_ring(?:\.[A-Za-z_]\w*)+", page.read_text(encoding="utf-8")))):
            parts = name.split(".")
            for cut in range(len(parts), 0, -1):
                try:
                    obj = importlib.import_module(".".join(parts[:cut]))
                except ImportError:
                    continue
                try:
                    for attr in parts[cut:]:
                        obj = getattr(obj, attr)
                except AttributeError:
                    missing.append(f"{page.name}: {name}")
                break
            else:
                missing.append(f"{page.name}: {name}")
    assert not missing, "\n".join(missing)


def test_example_names_in_the_docs_are_shipped():
    from uio_ring.cli.examples import example_names

    names = set(example_names())
    for page in PAGES:
        for ref in re.findall(r"`([a-z0-9_]+)\.yaml`", page.read_text(encoding="utf-8")):
            assert ref in names or ref in {"spec", "full_example"}, f"{page.name}: {ref}.yaml is not a shipped example"


def test_spec_format_page_lists_every_key_of_the_schema():
    """docs/spec-format.md documents every key a spec file accepts (the schema is the truth)."""
    from uio_ring.spec import schema

    page = (DOCS / "spec-format.md").read_text(encoding="utf-8")
    sch = schema()
    keys = set(sch["properties"])
    for section in ("system", "design", "simulate", "output"):
        keys |= set(sch["properties"][section].get("properties", {}))
    missing = sorted(k for k in keys if f"`{k}`" not in page)
    assert not missing, f"docs/spec-format.md does not document: {', '.join(missing)}"


def test_spec_format_page_lists_every_signal_function():
    from uio_ring.spec.expressions import FUNCTIONS

    page = (DOCS / "spec-format.md").read_text(encoding="utf-8")
    missing = [f for f in FUNCTIONS if not re.search(rf"\b{f}\b", page)]
    assert not missing, f"docs/spec-format.md does not list: {', '.join(missing)}"


@pytest.mark.parametrize("cls_name", ["DelayUIODesign", "NormalFormDesign"])
def test_notation_tables_name_real_attributes(cls_name):
    """The first column of each design table in docs/notation.md names attributes that exist."""
    import uio_ring

    cls = getattr(uio_ring, cls_name)
    page = (DOCS / "notation.md").read_text(encoding="utf-8")
    section = page.split(f"`{cls_name}`", 1)[1].split("\n\n`", 1)[0]
    names = [a for cell in re.findall(r"^\| (`[^|]*`) \|", section, re.M)
             for a in re.findall(r"`([A-Za-z_][A-Za-z_0-9]*)(?:\(\))?`", cell)]
    assert names, f"no table found for {cls_name}"
    fields = {f.name for f in dataclasses.fields(cls)}
    missing = [a for a in names if not hasattr(cls, a) and a not in fields]
    assert not missing, f"docs/notation.md names {missing} that {cls_name} does not have"
