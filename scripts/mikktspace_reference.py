"""Reference MikkTSpace tangents from Blender (mesh.calc_tangents(), Blender's port of mikktspace.c).

Run headless, once, to make tests/data/mikktspace/*.tangents.txt (see the README there):
  blender -b --factory-startup --python-exit-code 1 --python scripts/mikktspace_reference.py -- IN OUT

IN is a triangle OBJ (faces "f v/vt/vn", as MikktspaceReference.DISABLED_WriteInputs writes them) or a
.gltf. The OBJ is read here, not by Blender's importer, so that nothing is merged or reordered: one Blender
vertex per OBJ "v", one polygon per "f", loops in the file's corner order, the "vn" normals set as custom
split normals (auto smooth at 180 degrees, so no edge splits a smooth fan). The glTF goes through
bpy.ops.import_scene.gltf (no vertex merging); its +Y-up frame is converted back from Blender's +Z-up.

OUT gets one line per loop, three per triangle in polygon order:
  px py pz u v nx ny nz tx ty tz sign
position, uv, the normal Blender used (MikkTSpace takes normals as given), tangent and bitangent sign.
"""

import sys

import bpy


def read_obj(path):
    positions, uvs, normals, faces = [], [], [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts or parts[0].startswith("#"):
                continue
            if parts[0] == "v":
                positions.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "vt":
                uvs.append(tuple(float(x) for x in parts[1:3]))
            elif parts[0] == "vn":
                normals.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                corners = [tuple(int(i) - 1 for i in c.split("/")) for c in parts[1:]]
                if len(corners) != 3:
                    raise ValueError(f"{path}: not a triangle: {line.strip()}")
                faces.append(corners)
    return positions, uvs, normals, faces


def mesh_from_obj(path):
    positions, uvs, normals, faces = read_obj(path)
    mesh = bpy.data.meshes.new("reference")
    mesh.from_pydata(positions, [], [[c[0] for c in face] for face in faces])
    mesh.update()
    if len(mesh.polygons) != len(faces):
        raise RuntimeError(f"{path}: Blender kept {len(mesh.polygons)} of {len(faces)} faces")
    uv_layer = mesh.uv_layers.new(name="UVMap")
    loop_normals = []
    for poly, face in zip(mesh.polygons, faces):
        poly.use_smooth = True
        for loop_index, corner in zip(poly.loop_indices, face):
            if mesh.loops[loop_index].vertex_index != corner[0]:
                raise RuntimeError(f"{path}: loop order differs from the file")
            uv_layer.data[loop_index].uv = uvs[corner[1]]
            loop_normals.append(normals[corner[2]])
    mesh.use_auto_smooth = True
    mesh.auto_smooth_angle = 3.14159265
    mesh.normals_split_custom_set(loop_normals)
    return mesh, lambda v: (v[0], v[1], v[2])


def mesh_from_gltf(path):
    # Debian 12's Blender 3.4 glTF importer uses np.bool, which Debian 12's numpy 1.24 removed: alias it.
    import numpy as np

    if "bool" not in np.__dict__:
        np.bool = bool
    for obj in list(bpy.data.objects):  # the factory startup scene's cube, camera and light
        bpy.data.objects.remove(obj)
    bpy.ops.import_scene.gltf(filepath=path, merge_vertices=False)
    meshes = [o.data for o in bpy.context.scene.objects if o.type == "MESH"]
    if len(meshes) != 1:
        raise RuntimeError(f"{path}: expected one mesh, got {len(meshes)}")
    # Blender's glTF importer maps glTF (x, y, z) to Blender (x, -z, y); back:
    return meshes[0], lambda v: (v[0], v[2], -v[1])


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    if len(args) != 2:
        raise SystemExit("usage: blender -b --python mikktspace_reference.py -- IN OUT")
    src, dst = args
    mesh, to_file_frame = mesh_from_gltf(src) if src.endswith(".gltf") else mesh_from_obj(src)
    uv_name = mesh.uv_layers[0].name
    mesh.calc_normals_split()  # fills loop.normal (calc_tangents uses the same split normals)
    mesh.calc_tangents(uvmap=uv_name)
    with open(dst, "w") as out:
        out.write(f"# MikkTSpace reference: Blender {bpy.app.version_string}, mesh.calc_tangents(uvmap={uv_name!r})\n")
        out.write(f"# input: {src.split('/')[-1]}; command: blender -b --factory-startup --python-exit-code 1 "
                  f"--python scripts/mikktspace_reference.py -- {src.split('/')[-1]} {dst.split('/')[-1]}\n")
        out.write("# per loop, 3 per triangle: px py pz u v nx ny nz tx ty tz sign\n")
        uv_data = mesh.uv_layers[uv_name].data
        for poly in mesh.polygons:
            if poly.loop_total != 3:
                raise RuntimeError(f"{src}: polygon {poly.index} has {poly.loop_total} corners")
            for li in poly.loop_indices:
                loop = mesh.loops[li]
                p = to_file_frame(mesh.vertices[loop.vertex_index].co)
                n = to_file_frame(loop.normal)
                t = to_file_frame(loop.tangent)
                uv = uv_data[li].uv
                values = [*p, uv[0], uv[1], *n, *t, loop.bitangent_sign]
                out.write(" ".join(f"{x:.9g}" for x in values) + "\n")


main()
