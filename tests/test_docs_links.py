"""Every relative link of README.md and docs/*.md resolves to a file or folder of the repository."""

import pathlib
import re
import urllib.parse

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]
DOCS = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
#: a markdown link or image ``[text](target "title")``, an HTML ``src``/``href``, a reference definition ``[x]: t``
_LINK = re.compile(r"!?\[[^\]\n]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)|(?:src|href)=\"([^\"]+)\"|"
                   r"^\s*\[[^\]\n]+\]:\s+(\S+)", re.M)
_CODE = re.compile(r"```.*?```|`[^`\n]*`", re.S)


def relative_links(text: str) -> list[str]:
    """The relative targets (without their ``#anchor``) of the links of a markdown text, code left out.

    >>> relative_links("[a](docs/x.md#y) ![b](p.png) [c](https://x.org) `[d](no.md)` [e](#top)")
    ['docs/x.md', 'p.png']
    """
    out = []
    for m in _LINK.finditer(_CODE.sub("", text)):
        target = next(g for g in m.groups() if g)
        if re.match(r"[a-zA-Z][a-zA-Z0-9+.-]*:", target) or target.startswith("#"):
            continue  # a URL (http:, mailto:) or an anchor of the same page
        out.append(urllib.parse.unquote(target.split("#", 1)[0]))
    return out


@pytest.mark.parametrize("doc", DOCS, ids=[str(d.relative_to(REPO)) for d in DOCS])
def test_every_relative_link_resolves(doc):
    broken = [t for t in relative_links(doc.read_text(encoding="utf-8")) if not (doc.parent / t).exists()]
    assert not broken, f"{doc.relative_to(REPO)} links to {broken}, which do not exist (relative to {doc.parent.name}/)"


def test_the_check_finds_a_broken_link(tmp_path):
    doc = tmp_path / "a.md"
    doc.write_text("see [b](b.md) and [c](sub/c.md)\n")
    (tmp_path / "b.md").write_text("")
    assert [t for t in relative_links(doc.read_text()) if not (tmp_path / t).exists()] == ["sub/c.md"]
