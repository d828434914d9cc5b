#!/usr/bin/env python3
"""Import circles in src/: between the pipeline's stages (top-level modules) and between the files
of one folder.

Reads every `use crate::…` and `use super::…` (and `crate::a::b` paths written inline) outside
comments and `#[cfg(test)]` modules, maps each to the file that defines the module it names, and reports every
strongly connected component of more than one node:

    python3 tools/import_circles.py            # report; exit 0
    python3 tools/import_circles.py --check    # exit 1 if there is a circle (for CI)

Stages are the folders and files directly under src/ (`scene`, `surface`, `shading`, `render`,
…); within a folder the nodes are its files and sub-folders, and its mod.rs. A mod.rs's
re-exports (`pub use child::Name`) are not its dependencies: a file that uses such a name
depends on the child that defines it. Test modules are left out: a test
may reach across stages without making the product's stages depend on each other.
"""

import argparse
import re
import sys
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src"
PATH = re.compile(r"\b(crate|super)((?:::[A-Za-z_][A-Za-z0-9_]*)+)")


def module_of(file):
    """The module path of a source file: src/a/b.rs and src/a/b/mod.rs → ['a', 'b']."""
    parts = list(file.relative_to(SRC).with_suffix("").parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return parts


def product_text(text):
    """`text` without its comments (a doc link is not a dependency) and its `#[cfg(test)]` items
    (the module or function that follows)."""
    text = re.sub(r"(?m)^\s*//.*$", "", text)
    out, i = [], 0
    while True:
        j = text.find("#[cfg(test)]", i)
        if j < 0:
            out.append(text[i:])
            return "".join(out)
        out.append(text[i:j])
        brace = text.find("{", j)
        semi = text.find(";", j)
        if brace < 0 or (0 <= semi < brace):
            i = semi + 1  # `#[cfg(test)] mod tests;` or a one-line item
            continue
        depth, k = 0, brace
        while k < len(text):
            depth += {"{": 1, "}": -1}.get(text[k], 0)
            k += 1
            if depth == 0:
                break
        i = k


def expand_uses(text):
    """Every `use a::{b, c::{d, e}}` in `text` as the plain paths `a::b`, `a::c::d`, `a::c::e`
    (joined by newlines, appended), so that the path pattern sees each."""

    def expand(prefix, body):
        out, depth, item = [], 0, ""
        for ch in body + ",":
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
            if ch == "," and depth == 0:
                item = item.strip()
                if "{" in item:
                    head, inner = item.split("{", 1)
                    out += expand(prefix + head, inner.rsplit("}", 1)[0])
                elif item and item != "self":
                    out.append(prefix + item.split(" as ")[0].strip())
                elif item == "self":
                    out.append(prefix.rstrip(":"))
                item = ""
            else:
                item += ch
        return out

    paths = []
    for m in re.finditer(r"\buse\s+([A-Za-z_:]*)\{", text):
        depth, k = 1, m.end()
        while k < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[k], 0)
            k += 1
        paths += expand(m.group(1), text[m.end() : k - 1])
    return text + "\n" + "\n".join(p + "::_" for p in paths)


def reexports(file, modules):
    """Names a mod.rs re-exports from its children (`pub use child::Name`): name → child module."""
    here = module_of(file)
    out = {}
    text = expand_uses(product_text(file.read_text()))
    for path in re.findall(r"\bpub(?:\([^)]*\))?\s+use\s+(?:self::)?([A-Za-z_][A-Za-z0-9_:]*)", text):
        parts = path.split("::")
        if len(parts) >= 2 and tuple(here + [parts[0]]) in modules:
            out[parts[-1]] = tuple(here + [parts[0]])
    # The brace groups, expanded: `child::Name::_`.
    for child, name in re.findall(r"^([A-Za-z_][A-Za-z0-9_]*)::([A-Za-z_][A-Za-z0-9_]*)::_$", text, re.M):
        if tuple(here + [child]) in modules:
            out.setdefault(name, tuple(here + [child]))
    return out


def targets(file, modules, facades):
    """The modules `file` refers to, as the longest known module prefix of each path."""
    here = module_of(file)
    is_mod = file.name == "mod.rs"
    found = set()
    text = product_text(file.read_text())
    if is_mod:
        # A folder's re-exports (`pub use child::Name;`) are its interface, not a dependency of
        # its own code: whoever uses such a name is counted as using the child (see `reexports`).
        # A re-exported name that mod.rs's own code uses is a dependency, kept as `child::Name`.
        exports = re.findall(r"\bpub(?:\([^)]*\))?\s+use\s+([^;]*);", text)
        text = re.sub(r"\bpub(?:\([^)]*\))?\s+use\s+[^;]*;", "", text)
        body = re.sub(r"(?m)^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*;", "", text)
        used = []
        for tree in exports:
            # `a::{b, c}` expands to `a::b::_` and `a::c::_` after the text; a plain path is itself.
            paths = [p.removesuffix("::_") for p in expand_uses("use " + tree + ";").split("\n")[1:] if p]
            for path in paths or [tree]:
                name = path.split("::")[-1].split(" as ")[-1].strip()
                if re.search(r"(?<![A-Za-z0-9_:])" + re.escape(name) + r"\b", body):
                    used.append(path)
        text += "\n" + "\n".join(f"use self::{u};" for u in used)
    text = expand_uses(text)
    # Paths through a child module the file declares (`mod x;` … `x::f()`, `use x::T`, `self::x`).
    own = here
    for child in re.findall(r"^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+([A-Za-z_][A-Za-z0-9_]*)\s*;", text, re.M):
        for rest in re.findall(r"(?<![A-Za-z0-9_:])(?:self::)?" + child + r"((?:::[A-Za-z_][A-Za-z0-9_]*)*)::", text):
            full = own + [child] + [n for n in rest.split("::") if n]
            for n in range(len(full), 0, -1):
                if tuple(full[:n]) in modules:
                    found.add(tuple(full[:n]))
                    break
    for kind, rest in PATH.findall(text):
        names = rest.split("::")[1:]
        if kind == "crate":
            base = []
        else:
            base = here[:] if is_mod else here[:-1]
            while names and names[0] == "super":
                names.pop(0)
                base = base[:-1]
        full = base + names
        for n in range(len(full), 0, -1):
            if tuple(full[:n]) in modules:
                # A name a folder's mod.rs only re-exports belongs to the child it comes from.
                via = facades.get(tuple(full[:n]), {})
                if n < len(full) and full[n] in via:
                    found.add(via[full[n]])
                else:
                    found.add(tuple(full[:n]))
                break
    return found


def circles(graph):
    """Strongly connected components with more than one node (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def main():
    global SRC
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="exit 1 if there is a circle")
    p.add_argument("--src", type=Path, default=SRC, help="the source folder (default: this repository's src/)")
    args = p.parse_args()
    SRC = args.src.resolve()
    files = sorted(SRC.rglob("*.rs"))
    modules = {tuple(module_of(f)): f for f in files}
    facades = {tuple(module_of(f)): reexports(f, modules) for f in files if f.name in ("mod.rs", "lib.rs")}
    edges = {}
    for f in files:
        src = tuple(module_of(f))
        for t in targets(f, modules, facades):
            if t != src:
                edges.setdefault(src, set()).add(t)
    # Collapse to one level: stages (top level), and within each folder its direct children and
    # its mod.rs (a child reaching back into the folder's own items, which mod.rs uses in turn,
    # is a circle too).
    groups = {}
    for src, ts in edges.items():
        for t in ts:
            common = 0
            while common < min(len(src), len(t)) and src[common] == t[common]:
                common += 1
            folder = src[:common]
            a = src[common] if common < len(src) else "mod.rs"
            b = t[common] if common < len(t) else "mod.rs"
            if not folder and "mod.rs" in (a, b):
                continue  # lib.rs declares the stages
            groups.setdefault(folder, {}).setdefault(a, set()).add(b)
    found = []
    for folder, graph in sorted(groups.items()):
        for comp in circles(graph):
            where = "src/" + "/".join(folder) if folder else "the stages under src/"
            found.append(f"{where}: {' <-> '.join(comp)}")
    for line in found:
        print(f"circle in {line}")
    print(f"{len(found)} import circle(s)")
    sys.exit(1 if args.check and found else 0)


if __name__ == "__main__":
    main()
