"""Check every internal link of a built HTML site: the file exists, and so does the anchor.

Usage: ``python3 docs/_ext/check_links.py docs/_build/html``. Links to other sites
(``http:``, ``https:``, ``mailto:``, ...) are not followed (CI reaches no web site); every
relative ``href`` and ``src`` is. Exit status 1 and one line per broken link if any.
"""

from __future__ import annotations

import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit


class _Page(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.links: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if value is None:
                continue
            if name in ("id", "name"):
                self.ids.add(value)
            elif name in ("href", "src") and not (tag == "link" and name == "href"
                                                 and value.startswith("data:")):
                self.links.append(value)


def _parse(path: Path, cache: dict) -> _Page:
    if path not in cache:
        page = _Page()
        page.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = page
    return cache[path]


def broken_links(root: Path) -> list[str]:
    """``"page: link (why)"`` for every internal link of ``root/**/*.html`` that is broken."""
    root = root.resolve()
    cache: dict[Path, _Page] = {}
    bad = []
    for page_path in sorted(root.rglob("*.html")):
        if page_path.relative_to(root).parts[0] == "_static":
            continue  # the theme's template fragments, not pages
        for link in _parse(page_path, cache).links:
            parts = urlsplit(link)
            if parts.scheme or parts.netloc or link.startswith(("javascript:", "data:")):
                continue  # another site, or not a location
            target = page_path if not parts.path else \
                (page_path.parent / unquote(parts.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            where = page_path.relative_to(root)
            if not target.is_relative_to(root) or not target.exists():
                bad.append(f"{where}: {link} (no such file)")
            elif parts.fragment and target.suffix == ".html" and \
                    unquote(parts.fragment) not in _parse(target, cache).ids:
                bad.append(f"{where}: {link} (no such anchor)")
    return bad


def main(argv: list[str]) -> int:
    if len(argv) != 1 or not Path(argv[0]).is_dir():
        print(__doc__, file=sys.stderr)
        return 2
    bad = broken_links(Path(argv[0]))
    for line in bad:
        print(line)
    pages = sum(1 for p in Path(argv[0]).rglob("*.html") if "_static" not in p.parts)
    print(f"{len(bad)} broken internal links in {pages} pages")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
