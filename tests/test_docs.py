"""The documentation's links: every relative link of README.md, CHANGELOG.md and docs/*.md names a file or folder
that exists, and every page of docs/ is reachable from the README's index."""

import re

import pytest

from conftest import ROOT

PAGES = [ROOT / "README.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").glob("*.md"))]
LINK = re.compile(r"\]\(([^)\s]+)\)")


def links(page):
    return [m for m in LINK.findall(page.read_text()) if not re.match(r"^[a-z]+:|^#", m)]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_relative_link_exists(page):
    missing = [target for target in links(page) if not (page.parent / target.split("#")[0]).exists()]
    assert not missing, f"{page.name} links to missing files: {missing}"


def test_the_readme_indexes_every_docs_page():
    indexed = {(ROOT / t).resolve() for t in links(ROOT / "README.md")}
    assert {p.resolve() for p in (ROOT / "docs").glob("*.md")} <= indexed


def test_a_broken_link_is_found(tmp_path):
    """The check itself: a page linking to a missing file is caught."""
    page = tmp_path / "page.md"
    page.write_text("see [here](missing.md) and [there](https://example.org/x.md)")
    assert links(page) == ["missing.md"] and not (tmp_path / "missing.md").exists()
