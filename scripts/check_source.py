"""Checks of the source tree's habits, each a rule that can fail (scripts/check-source.sh runs them):

  layers    every #include in lib/ respects the layer order of lib/CMakeLists.txt: a file may
            include headers of its own layer and of the layers its layer links (PUBLIC, transitively);
            a public header's layer is that of the source whose own header it is, else the highest
            layer it includes.
  formats   no image format name or extension literal outside the format table's files (the
            table, the codecs and OpenImageIO's backends), in lib/, tools/, python/src and
            python/panoproj (less the files generate_api.py makes from the tables).
  variants  no std::get_if / std::holds_alternative / std::get on a projection alternative in
            lib/src/engine, lib/src/sampling, lib/src/photometry and lib/src/geometry: they ask a
            projection's module
            (its sampling facts). lib/src/simd/geometry.cpp's pair table (which fused kernel
            serves a pair of forms, made from each form's parameters) is the one dispatch allowed.

Prints each violation as "path:line: what" and exits 1 if there is any.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
LIB = ROOT / "lib"


def layers():
    """{layer: set of layers it may include (itself and its PUBLIC links, transitively)}, {source: layer}."""
    text = (LIB / "CMakeLists.txt").read_text()
    links, sources = {}, {}
    for m in re.finditer(r"panoproj_layer\((\w+)(.*?)\)\n", text, re.S):
        name, body = m.group(1), m.group(2)
        words = body.split()
        section = None
        links[name] = set()
        for w in words:
            if w in ("SOURCES", "PUBLIC", "PRIVATE"):
                section = w
            elif section == "SOURCES" and w.startswith("src/"):
                sources[w] = name
            elif section == "PUBLIC" and w.startswith("panoproj::"):
                links[name].add(w.split("::")[1])
    for extra in re.finditer(r"target_sources\(panoproj_(\w+) PRIVATE ([^)]*)\)", text):
        for w in extra.group(2).split():
            sources[w] = extra.group(1)
    allowed = {}
    for name in links:
        seen, todo = {name}, [name]
        while todo:
            for d in links[todo.pop()]:
                if d not in seen:
                    seen.add(d)
                    todo.append(d)
        allowed[name] = seen
    return allowed, sources


def includes(path):
    for n, line in enumerate(path.read_text().splitlines(), 1):
        m = re.match(r'\s*#include "([^"]+)"', line)
        if m:
            yield n, m.group(1)


def header_path(name):
    for base in (LIB / "include", LIB / "src"):
        if (base / name).exists():
            return base / name
    return None


def check_layers():
    allowed, sources = layers()
    rank = {name: len(deps) for name, deps in allowed.items()}  # deeper layers link more
    layer_of = {}  # path relative to lib/ -> layer
    for src, layer in sources.items():
        layer_of[src] = layer
        folder = str(pathlib.Path(src).parent)
        for h in (LIB / folder).glob("*.hpp"):
            layer_of.setdefault(str(h.relative_to(LIB)), layer)
        first = next(includes(LIB / src), None)  # a source's own header comes first
        if first and first[1].startswith("panoproj/") and pathlib.Path(first[1]).stem == pathlib.Path(src).stem:
            layer_of.setdefault("include/" + first[1], layer)

    def of_header(rel, stack=()):
        # A header of no layer's folder or source: the lowest layer that may include all it includes.
        if rel in layer_of:
            return layer_of[rel]
        needed = {"base"}
        for _, inc in includes(LIB / rel):
            p = header_path(inc)
            if p is not None and str(p.relative_to(LIB)) not in stack:
                needed.add(of_header(str(p.relative_to(LIB)), stack + (rel,)))
        fits = [name for name in allowed if needed <= allowed[name]]
        layer_of[rel] = min(fits, key=lambda name: len(allowed[name])) if fits else max(needed, key=lambda n: rank[n])
        return layer_of[rel]

    bad = []
    files = [p for p in LIB.rglob("*.[ch]pp")]
    for f in files:
        rel = str(f.relative_to(LIB))
        if rel not in layer_of and not rel.startswith("include/"):
            continue  # not in a layer (the OpenImageIO plugin, a module of its own)
        own = of_header(rel) if rel.startswith("include/") else layer_of[rel]
        for n, inc in includes(f):
            p = header_path(inc)
            if p is None:
                continue
            theirs = of_header(str(p.relative_to(LIB)))
            if theirs not in allowed[own]:
                bad.append(f"{f.relative_to(ROOT)}:{n}: the {own} layer includes {inc} (the {theirs} layer)")
    return bad


FORMAT_FILES = re.compile(r"lib/src/io/(formats\.[ch]pp|\w+_codec\.cpp|oiio_plugin\.cpp|oiio/backend\.cpp)$|python/src/oiio_package\.cpp$")
FORMAT_LITERAL = re.compile(r'(["\'])\.?(jpe?g|png|pnm|ppm|pgm|tiff?|openexr|exr|hdr)\1', re.I)
RANGE = re.compile(r'(["\'])ldr\1')
GENERATED = re.compile(r"python/panoproj/(_declared|_jobs)\.py$")  # made from the tables (generate_api.py)


def code_of(line):
    """The line without a // comment (outside string literals)."""
    out, quoted = [], False
    for i, c in enumerate(line):
        if c == '"' and (i == 0 or line[i - 1] != "\\"):
            quoted = not quoted
        if not quoted and line.startswith("//", i):
            break
        out.append(c)
    return "".join(out)


def code_lines(folders, skip=None):
    """(path relative to the root, line number, the line without its comment) of the C++ sources
    under folders, less the paths skip matches."""
    for folder in folders:
        for f in sorted((ROOT / folder).rglob("*.[ch]pp")):
            rel = str(f.relative_to(ROOT))
            if skip is None or not skip.search(rel):
                for n, line in enumerate(f.read_text().splitlines(), 1):
                    yield rel, n, code_of(line)


def python_lines(folder, skip):
    """(path, line number, the line without a # comment) of the Python files under folder."""
    for f in sorted((ROOT / folder).rglob("*.py")):
        rel = str(f.relative_to(ROOT))
        if not skip.search(rel):
            for n, line in enumerate(f.read_text().splitlines(), 1):
                yield rel, n, line.split("#")[0]


def check_formats():
    lines = [*code_lines(("lib/src", "lib/include", "tools", "python/src"), FORMAT_FILES),
             *python_lines("python/panoproj", GENERATED)]
    # "hdr" beside "ldr" is a dynamic range (stitch's output_mode), not the Radiance format.
    return [f"{rel}:{n}: format literal {m.group(0)} outside the format table (io/formats.hpp)"
            for rel, n, code in lines
            if (m := FORMAT_LITERAL.search(code)) and not (m.group(2).lower() == "hdr" and RANGE.search(code))]


def projection_types():
    text = (LIB / "include/panoproj/projections/list.hpp").read_text()
    return set(re.findall(r"X\((\w+)\)", text))


def check_variants():
    pattern = re.compile(r"std::(get_if|holds_alternative|get)<\s*(" + "|".join(sorted(projection_types())) + r")\s*>")
    return [f"{rel}:{n}: {m.group(0)} (ask the projection's module: sampling_facts)"
            for rel, n, code in code_lines(("lib/src/engine", "lib/src/sampling", "lib/src/photometry", "lib/src/geometry"))
            if (m := pattern.search(code))]


def main():
    checks = {"layers": check_layers, "formats": check_formats, "variants": check_variants}
    names = sys.argv[1:] or list(checks)
    bad = [line for name in names for line in checks[name]()]
    for line in bad:
        print(line)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
