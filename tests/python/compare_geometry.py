"""Compares the geometry of two folders of spheremap outputs: for every surface.ply and sphere.ply under
BASE, the file of the same path under NEW must have the same positions, triangles, theta and phi, bit for
bit (other vertex properties may differ: they are allowed to change). Binary little-endian PLY only.

Usage: compare_geometry.py BASE NEW    Exit 0: identical geometry everywhere; 1: a difference (listed).
"""
import os
import struct
import sys

SIZES = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8}
CODES = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f", "double": "d"}


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    elements = []
    for line in data[:end].decode("latin-1").splitlines():
        words = line.split()
        if words[:1] == ["element"]:
            elements.append((words[1], int(words[2]), []))
        elif words[:1] == ["property"]:
            elements[-1][2].append(words[1:])
    at = end
    out = {}
    for name, count, props in elements:
        columns = {p[-1]: [] for p in props}
        for _ in range(count):
            for p in props:
                if p[0] == "list":
                    n = struct.unpack_from("<" + CODES[p[1]], data, at)[0]
                    at += SIZES[p[1]]
                    columns[p[-1]].append(data[at:at + n * SIZES[p[2]]])
                    at += n * SIZES[p[2]]
                else:
                    columns[p[-1]].append(data[at:at + SIZES[p[0]]])
                    at += SIZES[p[0]]
        out[name] = columns
    return out


def main():
    base, new = sys.argv[1], sys.argv[2]
    compared, problems = 0, []
    for root, _, files in os.walk(base):
        for f in sorted(files):
            if f not in ("surface.ply", "sphere.ply"):
                continue
            a = os.path.join(root, f)
            b = os.path.join(new, os.path.relpath(a, base))
            if not os.path.exists(b):
                problems.append(f"missing: {b}")
                continue
            pa, pb = read_ply(a), read_ply(b)
            for element, keys in (("vertex", ("x", "y", "z", "theta", "phi")), ("face", ("vertex_indices",))):
                for key in keys:
                    if pa[element].get(key) != pb[element].get(key):
                        problems.append(f"{b}: {element} {key} differs")
            compared += 1
    print(f"{compared} PLY files compared, {len(problems)} difference(s)")
    for p in problems[:50]:
        print("  " + p)
    return 1 if problems or compared == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
