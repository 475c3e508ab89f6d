#!/usr/bin/env python3
"""Checks that every #include in include/, src/ and cli/ goes down the layers (CONTRIBUTING.md, "Layout").

A file belongs to the layer of its folder: include/spheremap/<layer>/ or src/<layer>/; the headers directly in
include/spheremap/ are the root layer. Prints each include that runs against the layers and exits 1 if any does.
"""
import os
import re
import sys

# What each layer may include besides itself. Keep in step with CONTRIBUTING.md.
ROOT = {"root"}
BASE = ROOT | {"util"}
ALLOWED = {
    "root": set(),
    "util": ROOT,
    "geometry": BASE,
    "io": BASE | {"geometry"},
    "molecule": BASE | {"geometry", "io"},
    "topology": BASE | {"geometry"},
    "graph": BASE,
    "shapes": BASE | {"geometry", "topology"},
    "surface": BASE | {"geometry", "molecule", "topology"},
    "repair": BASE | {"geometry", "topology", "graph", "surface", "molecule"},
    "sphere": BASE | {"geometry", "topology"},
    "metrics": BASE | {"geometry", "topology", "sphere"},
    "properties": BASE | {"geometry", "io", "molecule", "topology", "surface", "sphere", "metrics"},
    "pipeline": BASE | {"geometry", "io", "molecule", "topology", "graph", "shapes", "surface", "repair", "sphere",
                        "metrics", "properties"},
    "reproduction": BASE | {"geometry", "io", "molecule", "topology", "sphere", "metrics", "properties", "pipeline"},
    "render": BASE | {"geometry", "molecule", "topology", "shapes", "surface", "sphere", "metrics", "properties",
                      "pipeline", "reproduction"},
    "cli": None,  # the top: anything
}
# Single headers a layer may include although their layer is not allowed.
EXCEPTIONS = {("render", "io/atomic_file.hpp")}

INCLUDE = re.compile(r'^\s*#\s*include\s*["<]([^">]+)[">]')


def layer_of(path):
    parts = path.split(os.sep)
    if parts[0] == "cli":
        return "cli"
    if parts[:2] == ["include", "spheremap"]:
        return "root" if len(parts) == 3 else parts[2]
    if parts[0] == "src":
        return "root" if len(parts) == 2 else parts[1]
    return None


def resolve(including, target):
    """The repository path of an included file of ours, or None for system and library headers."""
    if target.startswith("spheremap/"):
        return os.path.join("include", target)
    candidate = os.path.normpath(os.path.join(os.path.dirname(including), target))
    return candidate if os.path.exists(candidate) else None


def main():
    top = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    os.chdir(top)
    problems = []
    for root in ("include", "src", "cli"):
        for folder, _, files in os.walk(root):
            for name in sorted(files):
                if not name.endswith((".hpp", ".cpp", ".h")):
                    continue
                path = os.path.join(folder, name)
                layer = layer_of(path)
                if layer not in ALLOWED:
                    problems.append(f"{path}: folder '{layer}' is not a known layer (add it to scripts/check-layers.py)")
                    continue
                allowed = ALLOWED[layer]
                for number, line in enumerate(open(path, encoding="utf-8", errors="replace"), 1):
                    match = INCLUDE.match(line)
                    if not match:
                        continue
                    target = resolve(path, match.group(1))
                    if target is None:
                        continue
                    target_layer = layer_of(target)
                    if allowed is None or target_layer == layer or target_layer in allowed:
                        continue
                    short = target.split("spheremap/", 1)[1] if target.startswith("include/") else target
                    if (layer, short) in EXCEPTIONS:
                        continue
                    problems.append(f"{path}:{number}: {layer}/ includes {match.group(1)} ({target_layer}/)")
    for p in problems:
        print(p)
    print(f"check-layers: {len(problems)} include(s) against the layers")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
