"""The user's documents link to files and sections that exist: every relative link of the
README and of docs/ names a file of the repository, and a link to a section of a Markdown
file names one of its headings (by the anchor a Markdown renderer gives it)."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
LINK = re.compile(r"\]\(([^)#\s]*)(#[^)\s]*)?\)")


def anchors(text: str) -> set[str]:
    """The anchors of a Markdown file's headings: lower case, punctuation but hyphens
    dropped, spaces made hyphens; a repeated heading gets -1, -2, ..."""
    seen: dict[str, int] = {}
    out = set()
    for heading in re.findall(r"^#+ (.*)$", re.sub(r"```.*?```", "", text, flags=re.S),
                              re.M):
        base = re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")
        n = seen.get(base, 0)
        seen[base] = n + 1
        out.add(base if n == 0 else f"{base}-{n}")
    return out


def test_anchors_follow_the_renderers_rule():
    text = "# The `refined` sweep\n## Cost, per case\n## Cost, per case\n```\n# not a heading\n```"
    assert anchors(text) == {"the-refined-sweep", "cost-per-case", "cost-per-case-1"}


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_resolves(doc):
    text = doc.read_text()
    broken = []
    for target, anchor in LINK.findall(text):
        if re.match(r"[a-z]+:", target):  # http(s), mailto: not checked here
            continue
        path = (doc.parent / target).resolve() if target else doc
        if not path.exists():
            broken.append(target)
        elif anchor and path.suffix == ".md" and anchor[1:] not in anchors(path.read_text()):
            broken.append(target + anchor)
    assert not broken, f"{doc.relative_to(ROOT)}: broken links {broken}"
