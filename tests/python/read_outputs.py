"""Reads a map's surface.ply and sphere.ply with the tools users have (Debian's python3-meshio and
python3-open3d): every numeric vertex property, the colours and the normals must come through; and the
glTF twins (surface.glb, sphere.glb) with Open3D's glTF reader (tinygltf).

Usage: read_outputs.py FOLDER PROPERTY...   (run with PATH=/usr/bin:/bin: the system's python3)
Exit 0: read; 1: a reader failed or lost a property; 77: neither meshio nor open3d is installed (skip).
"""
import os
import sys


def main():
    folder, properties = sys.argv[1], sys.argv[2:]
    checked = []
    try:
        import meshio
    except ImportError:
        meshio = None
    try:
        import open3d
    except ImportError:
        open3d = None
    if meshio is None and open3d is None:
        print("neither meshio nor open3d is installed")
        return 77
    for name in ("surface.ply", "sphere.ply"):
        path = f"{folder}/{name}"
        if meshio is not None:
            mesh = meshio.read(path)
            for p in properties + ["nx", "red", "atomid", "theta", "phi"]:
                key = p if p in ("nx", "red", "atomid", "theta", "phi") else f"vertex_{p}"
                if key not in mesh.point_data:
                    print(f"meshio: {path} lacks {key}; it has {sorted(mesh.point_data)}")
                    return 1
                if len(mesh.point_data[key]) != len(mesh.points):
                    print(f"meshio: {path}: {key} has another length than the points")
                    return 1
            if sum(len(c.data) for c in mesh.cells) == 0:
                print(f"meshio: {path}: no triangles")
                return 1
            checked.append(f"meshio {name}: {len(mesh.points)} points, {len(mesh.point_data)} properties")
        if open3d is not None:
            mesh = open3d.io.read_triangle_mesh(path)
            if len(mesh.vertices) == 0 or len(mesh.triangles) == 0:
                print(f"open3d: {path}: no vertices or triangles")
                return 1
            if not mesh.has_vertex_colors() or not mesh.has_vertex_normals():
                print(f"open3d: {path}: colours {mesh.has_vertex_colors()}, normals {mesh.has_vertex_normals()}")
                return 1
            # Open3D's triangle-mesh readers drop custom vertex properties; its point-cloud reader keeps them.
            names = set(open3d.t.io.read_point_cloud(path).point)
            missing = [p for p in properties if f"vertex_{p}" not in names]
            if missing:
                print(f"open3d (point cloud): {path} lacks {missing}; it has {sorted(names)}")
                return 1
            checked.append(f"open3d {name}: {len(mesh.vertices)} vertices, colours and normals, {len(names)} attributes")
        if open3d is not None and os.path.exists(path[:-4] + ".glb"):
            glb = open3d.io.read_triangle_mesh(path[:-4] + ".glb")  # tinygltf inside
            if len(glb.vertices) != len(open3d.io.read_triangle_mesh(path).vertices) or not glb.has_vertex_colors():
                print(f"open3d: {path[:-4]}.glb: {len(glb.vertices)} vertices, colours {glb.has_vertex_colors()}")
                return 1
            checked.append(f"open3d {name[:-4]}.glb: {len(glb.vertices)} vertices with colours")
    print("\n".join(checked))
    return 0


if __name__ == "__main__":
    sys.exit(main())
