#!/usr/bin/env python3
"""Folders as layers: every #include in lib/ must point to the including file's own folder or to
a folder of a lower layer, and the folders' include graph must have no cycle (docs/design.md).

A folder is lib/src/F and lib/include/glintscope/F together (methods/NAME counts as one folder).
Prints each include that runs up the layers, with file and line, and exits 1; exits 0 when none.
"""
import pathlib
import re
import sys

# Bottom to top; a folder may include folders on its own line or on lines above it.
LAYERS = [
    ["core"],
    ["numerics", "optics", "surface"],
    ["io", "generate", "prepare"],
    ["lobe"],
    ["wave", "normal_density", "fit"],
    ["methods"],
    ["pipeline"],
    ["bsdf"],
    ["output"],
    ["render"],
    ["maps", "validate", "batch"],
    ["umbrella"],  # lib/include/glintscope/glintscope.hpp, the one include of the core API
]
RANK = {name: rank for rank, names in enumerate(LAYERS) for name in names}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def folder_of(relative):
    """The folder node of a path below lib/src or lib/include/glintscope."""
    parts = pathlib.PurePosixPath(relative).parts
    if parts[0] == "methods" and len(parts) > 2:
        return "methods/" + parts[1]
    return parts[0] if len(parts) > 1 else "umbrella"


def rank_of(folder):
    return RANK.get(folder.split("/")[0])


def resolve(root, source, target):
    """The folder an include names, or None for a header outside lib/."""
    if target.startswith("glintscope/"):
        return folder_of(target[len("glintscope/"):])
    local = (source.parent / target).resolve()
    for base in (root / "lib/src", root / "lib/include/glintscope"):
        if local.is_relative_to(base.resolve()) and local.exists():
            return folder_of(str(local.relative_to(base.resolve())))
    if (root / "lib/src" / target).exists():
        return folder_of(target)
    return None


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent)
    problems, edges = [], {}
    for base in (root / "lib/src", root / "lib/include/glintscope"):
        for path in sorted(base.rglob("*.[ch]pp")):
            here = folder_of(str(path.relative_to(base)))
            if here is None or rank_of(here) is None:
                problems.append(f"{path.relative_to(root)}: folder '{here}' has no layer in scripts/check-layers.py")
                continue
            for number, line in enumerate(path.read_text().splitlines(), 1):
                match = INCLUDE.match(line)
                if not match:
                    continue
                there = resolve(root, path, match.group(1))
                if there is None or there == here:
                    continue
                if rank_of(there) is None:
                    problems.append(f"{path.relative_to(root)}:{number}: includes folder '{there}', which has no layer")
                    continue
                edges.setdefault(here, set()).add(there)
                if rank_of(there) > rank_of(here):
                    problems.append(f"{path.relative_to(root)}:{number}: {here} (layer {rank_of(here)}) includes "
                                    f"{match.group(1)} from {there} (layer {rank_of(there)}), a higher layer")
    # Folders of one layer (the methods) may include each other, but never in a cycle.
    state = {}

    def visit(node, trail):
        state[node] = "open"
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == "open":
                problems.append("include cycle: " + " -> ".join(trail[trail.index(nxt):] + [nxt]))
            elif nxt not in state:
                visit(nxt, trail + [nxt])
        state[node] = "done"

    for node in sorted(edges):
        if node not in state:
            visit(node, [node])
    for problem in problems:
        print(problem)
    print(f"{len(edges)} folders, {sum(len(v) for v in edges.values())} folder edges, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
