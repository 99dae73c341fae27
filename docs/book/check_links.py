#!/usr/bin/env python3
"""Check the links of the built guide: every relative link of every page
reaches a file of the book, and every #anchor an id on its page; every
page of docs/ is a chapter. Usage: check_links.py BOOK_DIR (the build
folder, e.g. target/book). Exits 1 with one line per broken link."""

import re
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

# Pages mdBook writes besides the chapters: the print page repeats every
# chapter with its links rewritten, the others hold no chapter links.
SKIP = {"print.html", "toc.html", "404.html"}


class Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids = set()
        self.links = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("id", "name") and value:
                self.ids.add(value)
            if value and ((tag == "a" and name == "href") or (tag == "img" and name == "src")):
                self.links.append(value)


def parse(path, cache):
    if path not in cache:
        page = Page()
        page.feed(path.read_text(encoding="utf-8"))
        cache[path] = page
    return cache[path]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    book = Path(sys.argv[1]).resolve()
    docs = Path(__file__).resolve().parent.parent
    errors = []
    chapters = set(re.findall(r"\]\(([^)#]+\.md)\)", (docs / "SUMMARY.md").read_text()))
    for page in sorted(docs.glob("*.md")):
        if page.name != "SUMMARY.md" and page.name not in chapters:
            errors.append(f"docs/{page.name}: not a chapter of docs/SUMMARY.md")
    cache = {}
    pages = [p for p in sorted(book.rglob("*.html")) if p.name not in SKIP]
    if not pages:
        sys.exit(f"{book}: no pages: build the book first (mdbook build docs/book)")
    checked = 0
    for html in pages:
        rel = html.relative_to(book)
        for link in parse(html, cache).links:
            parts = urlsplit(link)
            if parts.scheme or link.startswith("//"):
                continue
            target = html if not parts.path else (html.parent / unquote(parts.path)).resolve()
            checked += 1
            if book not in target.parents and target != book:
                errors.append(f"{rel}: {link}: leaves the book")
            elif target.is_dir():
                if not (target / "index.html").is_file():
                    errors.append(f"{rel}: {link}: a folder without index.html")
            elif not target.is_file():
                errors.append(f"{rel}: {link}: no such file")
            elif parts.fragment and target.suffix == ".html":
                if unquote(parts.fragment) not in parse(target, cache).ids:
                    errors.append(f"{rel}: {link}: no such anchor")
    for line in errors:
        print(line)
    print(f"{len(pages)} pages, {checked} links checked, {len(errors)} broken")
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()
