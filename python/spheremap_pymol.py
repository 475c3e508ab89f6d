"""Loads a spheremap output folder into PyMOL: the surface overlaid on the structure and the sphere map
beside it, both coloured by any surface property, with a colour bar.

    PyMOL> run spheremap_pymol.py
    PyMOL> spheremap_load out/, property=electrostatics

The surface and the sphere are built as CGO triangles from surface.ply and sphere.ply (PyMOL's own PLY
loader scales coordinates by 100 and drops the properties). The structure is the input named in
report.json, loaded when the file exists (or give structure=FILE). Needs binary or ASCII PLY files written
by spheremap map; pure Python (no numpy).
"""
import json
import math
import os
import struct

from pymol import cgo, cmd

_SIZES = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8,
          "int8": 1, "uint8": 1, "int16": 2, "uint16": 2, "int32": 4, "uint32": 4, "float32": 4, "float64": 8}
_CODES = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f",
          "double": "d", "int8": "b", "uint8": "B", "int16": "h", "uint16": "H", "int32": "i", "uint32": "I",
          "float32": "f", "float64": "d"}

# The colour scales of spheremap (src/properties/colour_scale.cpp): control points, interpolated in sRGB.
_VIRIDIS = [(0.267, 0.005, 0.329), (0.283, 0.141, 0.458), (0.254, 0.265, 0.530), (0.207, 0.372, 0.553),
            (0.164, 0.471, 0.558), (0.128, 0.567, 0.551), (0.135, 0.659, 0.518), (0.267, 0.749, 0.441),
            (0.478, 0.821, 0.318), (0.741, 0.873, 0.150), (0.993, 0.906, 0.144)]
_RED_WHITE_BLUE = [(0.404, 0.0, 0.122), (0.698, 0.094, 0.169), (0.839, 0.376, 0.302), (0.957, 0.647, 0.510),
                   (0.992, 0.859, 0.780), (0.969, 0.969, 0.969), (0.820, 0.898, 0.941), (0.573, 0.773, 0.871),
                   (0.263, 0.576, 0.765), (0.129, 0.400, 0.675), (0.020, 0.188, 0.380)]
_TABLEAU = [(0.122, 0.467, 0.706), (1.0, 0.498, 0.055), (0.173, 0.627, 0.173), (0.839, 0.153, 0.157),
            (0.580, 0.404, 0.741), (0.549, 0.337, 0.294), (0.890, 0.467, 0.761), (0.498, 0.498, 0.498),
            (0.737, 0.741, 0.133), (0.090, 0.745, 0.812)]
_MISSING = (0.5, 0.5, 0.5)


def read_ply(path):
    """Vertex columns (name -> list of numbers; lists skipped) and triangles of a PLY file of spheremap."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("latin-1").splitlines()
    ascii_format = any(line.startswith("format ascii") for line in header)
    elements = []
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            elements.append((words[1], int(words[2]), []))
        elif words[:1] == ["property"]:
            elements[-1][2].append(words[1:])
    vertex, faces = {}, []
    if ascii_format:
        tokens = data[end:].split()
        at = 0
        for name, count, props in elements:
            for _ in range(count):
                if name == "face":
                    n = int(tokens[at])
                    faces.append([int(t) for t in tokens[at + 1:at + 1 + n]])
                    at += 1 + n
                    continue
                for p in props:
                    if p[0] == "list":
                        at += 1 + int(tokens[at])
                    else:
                        vertex.setdefault(p[-1], []).append(float(tokens[at]))
                        at += 1
        return vertex, faces
    at = end
    for name, count, props in elements:
        if name == "vertex":
            scalar = all(p[0] != "list" for p in props)
            if scalar:  # one struct for the whole row
                row = struct.Struct("<" + "".join(_CODES[p[0]] for p in props))
                columns = [[] for _ in props]
                for values in row.iter_unpack(data[at:at + row.size * count]):
                    for c, v in zip(columns, values):
                        c.append(v)
                vertex = {p[-1]: c for p, c in zip(props, columns)}
                at += row.size * count
                continue
            for _ in range(count):
                for p in props:
                    if p[0] == "list":
                        n = struct.unpack_from("<" + _CODES[p[1]], data, at)[0]
                        at += _SIZES[p[1]] + n * _SIZES[p[2]]
                    else:
                        vertex.setdefault(p[-1], []).append(struct.unpack_from("<" + _CODES[p[0]], data, at)[0])
                        at += _SIZES[p[0]]
        elif name == "face":
            for _ in range(count):
                n = data[at]
                faces.append(list(struct.unpack_from("<%di" % n, data, at + 1)))
                at += 1 + 4 * n
    return vertex, faces


def _ramp(points, t):
    t = min(max(t, 0.0), 1.0) * (len(points) - 1)
    k = min(int(t), len(points) - 2)
    f = t - k
    return tuple(a + (b - a) * f for a, b in zip(points[k], points[k + 1]))


def colour_of(value, scale, lo, hi):
    """spheremap's colour of a value on a scale (grey for no value)."""
    if value is None or math.isnan(value):
        return _MISSING
    if scale == "categorical":
        return _TABLEAU[int(round(value)) % len(_TABLEAU)] if value >= 0 else _MISSING
    t = 0.5 if hi <= lo else (value - lo) / (hi - lo)
    return _ramp(_RED_WHITE_BLUE if scale == "diverging" else _VIRIDIS, t)


def _property_info(folder, name, values):
    """Scale and colour range of a property: from report.json, else the data's range."""
    info = {}
    report = os.path.join(folder, "report.json")
    if os.path.exists(report):
        with open(report) as f:
            info = json.load(f).get("properties", {}).get(name, {})
    scale = info.get("scale", "sequential")
    finite = [v for v in values if not math.isnan(v)]
    if info.get("default_range"):
        lo, hi = info["default_range"]
    elif finite:
        lo, hi = min(finite), max(finite)
        if scale == "diverging":
            lo, hi = -max(abs(lo), abs(hi)), max(abs(lo), abs(hi))
    else:
        lo, hi = 0.0, 1.0
    return scale, lo, hi, info.get("unit", "")


def _triangles(positions, normals, colours, faces, transform=None):
    obj = [cgo.BEGIN, cgo.TRIANGLES]
    for face in faces:
        for v in face[:3]:
            p = positions[v] if transform is None else transform(positions[v])
            obj.extend([cgo.COLOR, *colours[v], cgo.NORMAL, *normals[v], cgo.VERTEX, *p])
    obj.append(cgo.END)
    return obj


def spheremap_load(folder, property="electrostatics", structure=None, sphere=1, prefix=None):
    """Loads FOLDER (a spheremap map output): objects <prefix>_surface, <prefix>_sphere, the structure,
    and a colour bar <prefix>_bar for PROPERTY (any vertex_<name> of the PLY files)."""
    folder = os.path.expanduser(str(folder))
    prefix = prefix or os.path.basename(os.path.normpath(folder)) or "spheremap"
    surface, faces = read_ply(os.path.join(folder, "surface.ply"))
    key = "vertex_" + property
    if key not in surface:
        names = sorted(k[7:] for k in surface if k.startswith("vertex_"))
        raise ValueError("%s: no property '%s' (there are: %s)" % (folder, property, ", ".join(names)))
    values = [float(v) for v in surface[key]]
    scale, lo, hi, unit = _property_info(folder, property, values)
    colours = [colour_of(v, scale, lo, hi) for v in values]
    positions = list(zip(surface["x"], surface["y"], surface["z"]))
    normals = list(zip(surface.get("nx", [0.0] * len(values)), surface.get("ny", [0.0] * len(values)),
                       surface.get("nz", [1.0] * len(values))))
    cmd.load_cgo(_triangles(positions, normals, colours, faces), prefix + "_surface")

    if structure is None:
        report = os.path.join(folder, "report.json")
        if os.path.exists(report):
            with open(report) as f:
                candidate = json.load(f).get("input", "")
            if candidate and os.path.exists(candidate) and not candidate.lower().endswith((".obj", ".off", ".ply", ".stl")):
                structure = candidate
    if structure:
        cmd.load(structure, prefix + "_structure")
        cmd.show_as("sticks", prefix + "_structure")

    if int(sphere):
        # The sphere beside the molecule, scaled to it: radius = half the surface's largest extent.
        lows = [min(c) for c in zip(*positions)]
        highs = [max(c) for c in zip(*positions)]
        centre = [(a + b) / 2 for a, b in zip(lows, highs)]
        radius = max(b - a for a, b in zip(lows, highs)) / 2
        shift = (centre[0] + 2.5 * radius, centre[1], centre[2])
        points, _ = read_ply(os.path.join(folder, "sphere.ply"))
        unit_points = list(zip(points["x"], points["y"], points["z"]))
        cmd.load_cgo(_triangles(unit_points, unit_points, colours, faces,
                                lambda p: (shift[0] + radius * p[0], shift[1] + radius * p[1],
                                           shift[2] + radius * p[2])),
                     prefix + "_sphere")

    if scale == "categorical":
        finite = sorted({int(round(v)) for v in values if not math.isnan(v)})
        lo, hi = (finite[0], finite[-1]) if finite else (0, 1)
        stops = [lo + (hi - lo) * k / 9.0 for k in range(10)] if hi > lo else [lo, lo + 1]
        bar_colours = [list(colour_of(round(s), scale, lo, hi)) for s in stops]
    else:
        stops = [lo + (hi - lo) * k / 10.0 for k in range(11)]
        bar_colours = [list(colour_of(s, scale, lo, hi)) for s in stops]
    cmd.ramp_new(prefix + "_bar", "none", stops, bar_colours)
    print("spheremap: %s coloured by %s (%s, %s to %s %s)" % (folder, property, scale, lo, hi, unit))
    cmd.zoom(prefix + "_*")


cmd.extend("spheremap_load", spheremap_load)
