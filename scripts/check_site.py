"""Checks a built documentation site: every internal link, anchor, picture and script of its
pages resolves (a file that exists, an id on the page it names), and nothing is loaded from the
network (no script, style or picture from another host). External links are listed in
SITE/external_links.txt, not fetched. Exit 1 with one line per problem.
Usage: check_site.py SITE"""

import html.parser
import pathlib
import sys
import urllib.parse


class _Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.links, self.loads = set(), [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("id", "name"):
            if a.get(key) and (key == "id" or tag == "a"):
                self.ids.add(a[key])
        if tag == "a" and a.get("href"):
            self.links.append(a["href"])
        for key, tags in (("src", ("img", "script", "iframe", "source")), ("href", ("link",))):
            if tag in tags and a.get(key):
                self.loads.append(a[key])


def _parse(path, cache):
    if path not in cache:
        page = _Page()
        page.feed(path.read_text(encoding="utf-8"))
        cache[path] = page
    return cache[path]


def main(site):
    site = pathlib.Path(site).resolve()
    pages = sorted(p for p in site.rglob("*.html") if "_static" not in p.parts and ".doctrees" not in p.parts)
    cache, problems, external = {}, [], set()
    for page_path in pages:
        page = _parse(page_path, cache)
        where = page_path.relative_to(site)
        for url, loaded in [(u, False) for u in page.links] + [(u, True) for u in page.loads]:
            parts = urllib.parse.urlsplit(url)
            if parts.scheme in ("http", "https", "mailto") or url.startswith("//"):
                if loaded:
                    problems.append(f"{where}: loads {url} from the network")
                external.add(url)
                continue
            if parts.scheme:
                problems.append(f"{where}: link {url} of scheme {parts.scheme}")
                continue
            target = page_path if not parts.path else (page_path.parent / urllib.parse.unquote(parts.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            if site not in target.parents and target != site:
                problems.append(f"{where}: {url} leaves the site")
            elif not target.is_file():
                problems.append(f"{where}: {url} names a missing file")
            elif parts.fragment and target.suffix == ".html" and parts.fragment not in _parse(target, cache).ids:
                problems.append(f"{where}: {url} names a missing anchor")
    (site / "external_links.txt").write_text("".join(u + "\n" for u in sorted(external)))
    for p in problems:
        print(f"check_site: {p}", file=sys.stderr)
    print(f"check_site: {len(pages)} pages, {sum(len(cache[p].links) for p in pages)} links checked, "
          f"{len(external)} external (listed in external_links.txt, not fetched), {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
