"""Generates the Gmsh test meshes of tecon-mesh (run once; outputs are committed).

    pip install gmsh && python3 make_msh.py

Writes, next to this script:
  two_blocks.msh       ASCII MSH 4.1: two unit squares side by side, separate nodes
                       on x = 1 (physical surfaces left/right, curves west, east,
                       left_face, right_face, bottom, top)
  two_blocks_bin.msh   the same mesh, binary MSH 4.1
  plate_hole.msh       ASCII: unstructured square with a hole (surface plate,
                       curves outer, hole)
  quads.msh            recombined quadrilaterals (unsupported element type)
  old_format.msh       MSH 2.2 (unsupported version)
  reference.json       node/triangle counts and areas computed here from Gmsh's data
"""
import json
import gmsh


def tri_area(coords, tags, tris):
    idx = {t: i for i, t in enumerate(tags)}
    a = 0.0
    for k in range(0, len(tris), 3):
        p = [coords[3 * idx[tris[k + j]]: 3 * idx[tris[k + j]] + 2] for j in range(3)]
        a += 0.5 * abs((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
    return a


def stats():
    tags, coords, _ = gmsh.model.mesh.getNodes()
    types, _, nodes = gmsh.model.mesh.getElements(2)
    ntri = 0
    area = 0.0
    for t, n in zip(types, nodes):
        if t == 2:
            ntri += len(n) // 3
            area += tri_area(coords, list(tags), list(n))
    used = set()
    for t, n in zip(types, nodes):
        used.update(n)
    return {"nodes_used_by_triangles": len(used), "triangles": ntri, "area": area}


ref = {}
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)

# two blocks
gmsh.model.add("two_blocks")
occ = gmsh.model.geo
p = [occ.addPoint(x, y, 0) for (x, y) in [(0, 0), (1, 0), (1, 1), (0, 1)]]
q = [occ.addPoint(x, y, 0) for (x, y) in [(1, 0), (2, 0), (2, 1), (1, 1)]]
l1 = [occ.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
l2 = [occ.addLine(q[i], q[(i + 1) % 4]) for i in range(4)]
s1 = occ.addPlaneSurface([occ.addCurveLoop(l1)])
s2 = occ.addPlaneSurface([occ.addCurveLoop(l2)])
occ.synchronize()
for c in l1 + l2:
    gmsh.model.mesh.setTransfiniteCurve(c, 5)
gmsh.model.addPhysicalGroup(2, [s1], name="left")
gmsh.model.addPhysicalGroup(2, [s2], name="right")
gmsh.model.addPhysicalGroup(1, [l1[3]], name="west")
gmsh.model.addPhysicalGroup(1, [l2[1]], name="east")
gmsh.model.addPhysicalGroup(1, [l1[1]], name="left_face")
gmsh.model.addPhysicalGroup(1, [l2[3]], name="right_face")
gmsh.model.addPhysicalGroup(1, [l1[0], l2[0]], name="bottom")
gmsh.model.addPhysicalGroup(1, [l1[2], l2[2]], name="top")
gmsh.model.mesh.generate(2)
ref["two_blocks"] = stats()
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.option.setNumber("Mesh.Binary", 0)
gmsh.write("two_blocks.msh")
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.write("two_blocks_bin.msh")
gmsh.option.setNumber("Mesh.Binary", 0)
gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
gmsh.write("old_format.msh")
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.model.remove()

# plate with a hole
gmsh.model.add("plate_hole")
g = gmsh.model.geo
c = [g.addPoint(x, y, 0, 0.1) for (x, y) in [(0, 0), (1, 0), (1, 1), (0, 1)]]
outer = [g.addLine(c[i], c[(i + 1) % 4]) for i in range(4)]
o = g.addPoint(0.5, 0.5, 0, 0.05)
h = [g.addPoint(0.5 + 0.2 * dx, 0.5 + 0.2 * dy, 0, 0.05) for (dx, dy) in [(1, 0), (0, 1), (-1, 0), (0, -1)]]
arcs = [g.addCircleArc(h[i], o, h[(i + 1) % 4]) for i in range(4)]
s = g.addPlaneSurface([g.addCurveLoop(outer), g.addCurveLoop(arcs)])
g.synchronize()
gmsh.model.addPhysicalGroup(2, [s], name="plate")
gmsh.model.addPhysicalGroup(1, outer, name="outer")
gmsh.model.addPhysicalGroup(1, arcs, name="hole")
gmsh.model.mesh.generate(2)
ref["plate_hole"] = stats()
gmsh.write("plate_hole.msh")
gmsh.model.remove()

# quads
gmsh.model.add("quads")
g = gmsh.model.geo
c = [g.addPoint(x, y, 0, 0.5) for (x, y) in [(0, 0), (1, 0), (1, 1), (0, 1)]]
ls = [g.addLine(c[i], c[(i + 1) % 4]) for i in range(4)]
s = g.addPlaneSurface([g.addCurveLoop(ls)])
g.synchronize()
for l in ls:
    gmsh.model.mesh.setTransfiniteCurve(l, 3)
gmsh.model.mesh.setTransfiniteSurface(s)
gmsh.model.mesh.setRecombine(2, s)
gmsh.model.addPhysicalGroup(2, [s], name="square")
gmsh.model.mesh.generate(2)
gmsh.write("quads.msh")
gmsh.finalize()

with open("reference.json", "w") as f:
    json.dump(ref, f, indent=2)
