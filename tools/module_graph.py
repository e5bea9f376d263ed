#!/usr/bin/env python3
"""The crate's module graph from its `use` paths: rooms, arrows and circles.

A room is a top-level module of `src/` (a folder or a file); a file is one
`.rs` module. An arrow A -> B means some file of A names `crate::B...` (or,
for files, the module that path resolves to). Test files (`tests.rs`,
`*_tests.rs`) and `#[cfg(test)]` blocks are left out: they may import
anything. Circles are the strongly connected components with more than one
member, at both levels.

    python3 tools/module_graph.py            # summary
    python3 tools/module_graph.py --arrows   # and every room arrow
    python3 tools/module_graph.py --src OTHER/src   # another checkout
"""
import argparse
import pathlib
import re
import sys

SRC = pathlib.Path(__file__).resolve().parent.parent / "src"
PATH_RE = re.compile(r"\b(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)+)")


def module_of(path):
    """The module path of a source file: src/a/b.rs and src/a/b/mod.rs are a::b."""
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return tuple(parts)


def non_test_text(text):
    """The file without its `#[cfg(test)]` items (a brace-counted skip)."""
    out, i = [], 0
    while True:
        at = text.find("#[cfg(test)]", i)
        if at < 0:
            out.append(text[i:])
            return "".join(out)
        out.append(text[i:at])
        brace = text.find("{", at)
        semi = text.find(";", at)
        if semi >= 0 and (brace < 0 or semi < brace):
            i = semi + 1
            continue
        depth, j = 0, brace
        while j < len(text):
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
            if depth == 0:
                break
        i = j


def resolve(modules, here, head, tail):
    """The longest known module that `head::tail` names from module `here`."""
    names = tail.split("::")[1:]
    if head == "crate":
        base = ()
    elif head == "super":
        base = here[:-1]
        while names and names[0] == "super":
            base, names = base[:-1], names[1:]
    else:
        base = here
    for n in range(len(names), -1, -1):
        cand = base + tuple(names[:n])
        if cand in modules:
            return cand
    return None


def components(nodes, edges):
    """Tarjan's strongly connected components (iterative)."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for root in nodes:
        if root in index:
            continue
        work = [(root, iter(sorted(edges.get(root, ()))))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                out.append(comp)
    return out


def main():
    global SRC
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arrows", action="store_true", help="print every room arrow")
    ap.add_argument("--src", type=pathlib.Path, default=SRC, help="the crate's src folder")
    args = ap.parse_args()
    SRC = args.src.resolve()
    files = [
        p
        for p in sorted(SRC.rglob("*.rs"))
        if "bin" not in p.relative_to(SRC).parts[:1]
        and p.name != "tests.rs"
        and not p.name.endswith("_tests.rs")
    ]
    modules = {module_of(p): p for p in files}
    file_edges, room_edges = {}, {}
    for mod, path in modules.items():
        text = non_test_text(path.read_text(encoding="utf-8"))
        for head, tail in PATH_RE.findall(text):
            target = resolve(modules, mod, head, tail)
            if target is None or target == mod or not target:
                continue
            if target[: len(mod)] == mod or mod[: len(target)] == target:
                continue  # a parent and its child are one unit
            file_edges.setdefault(mod, set()).add(target)
            if mod and target[0] != mod[0]:
                room_edges.setdefault(mod[0], set()).add(target[0])
    rooms = sorted({m[0] for m in modules if m})
    room_circles = [c for c in components(rooms, room_edges) if len(c) > 1]
    file_circles = [c for c in components(sorted(modules), file_edges) if len(c) > 1]
    arrows = sum(len(v) for v in room_edges.values())
    print(f"{len(rooms)} top-level modules, {arrows} arrows between them, "
          f"{len(room_circles)} circles between rooms, {len(file_circles)} between files")
    for c in room_circles:
        print("room circle:", " -> ".join(sorted(c)))
    for c in file_circles:
        print("file circle:", ", ".join("::".join(m) for m in sorted(c)))
    if args.arrows:
        for r in rooms:
            print(f"{r} -> {', '.join(sorted(room_edges.get(r, ()))) or '(nothing)'}")
    return 1 if room_circles or file_circles else 0


if __name__ == "__main__":
    sys.exit(main())
