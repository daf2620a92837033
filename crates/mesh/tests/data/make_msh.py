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

    python3 make_msh.py rings

writes only the second-order and curved-interface meshes (and leaves the others):
  rings_p2.msh         two concentric full rings r = 1 | 1.5 | 2, meshed with Gmsh's
                       second-order elements (6-node triangles, 3-node lines; mid
                       nodes on the circles), separate nodes on r = 1.5
                       (surfaces inner, outer; curves bore, inner_face,
                       outer_face, surface)
  vessel_sector_lc002.msh      an 8° sector of the vessel's core and layer
                       (r = 0.762 | 0.7747 | 0.7811 m), lc = 0.002 m, refined to
                       0.0005 m at θ = 0 on the interface; the two interface
                       arcs are separate curves, so Gmsh places their nodes a
                       little apart (jitter); linear triangles
  vessel_sector_lc002_p2.msh   the same over 3°, second order
  mixed_orders.msh     written by hand: one 6-node and one 3-node triangle
  rings_reference.json counts and facing distances computed here from Gmsh's data

    python3 make_msh.py diagnostics

writes only the meshes of the import diagnostics (tests/gmsh_messages.rs):
  groups.msh           unit square (surface plate); curve y = 0 in two physical
                       curves (bottom, supported), x = 1 in supported; physical
                       points corner (0, 0) and centre (0.5, 0.5, a point not
                       embedded in the surface); physical curve ghost and
                       physical volume vol that hold no entity (as after an
                       OpenCASCADE boolean renumbers the entities)
  surface_two_groups.msh  unit square in two physical surfaces, plate and steel
  unmerged.msh         two unit squares side by side, each with its own points
                       and curves, in one physical surface plate (coincident
                       nodes on x = 1 within one region)
  plate_mm.msh         a 200 x 100 plate drawn in millimetres (surface plate,
                       curves left, right)
  plate_m.msh          the same, saved with Mesh.ScalingFactor = 0.001 (metres)
"""
import json
import math
import sys

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


def linear_meshes():
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


def ring_pair(name, radii, lc, order, span=None, lc_corner=None):
    """Two concentric rings (or ring sectors 0 <= θ <= span), each its own surface
    with its own curves on the middle radius."""
    gmsh.model.add(name)
    g = gmsh.model.geo

    def ring(ri, ro, inner_face):
        o = g.addPoint(0, 0, 0, lc)
        if span is None:
            pi = [g.addPoint(ri * math.cos(k * math.pi / 2), ri * math.sin(k * math.pi / 2), 0, lc) for k in range(4)]
            po = [g.addPoint(ro * math.cos(k * math.pi / 2), ro * math.sin(k * math.pi / 2), 0, lc) for k in range(4)]
            ai = [g.addCircleArc(pi[k], o, pi[(k + 1) % 4]) for k in range(4)]
            ao = [g.addCircleArc(po[k], o, po[(k + 1) % 4]) for k in range(4)]
            s = g.addPlaneSurface([g.addCurveLoop(ao), g.addCurveLoop(ai)])
            return s, ai, ao, [], []
        # the interface end at θ = 0 gets lc_corner (a weld-corner-like refinement)
        lca = lc_corner if (lc_corner and not inner_face) else lc
        lcb = lc_corner if (lc_corner and inner_face) else lc
        a = g.addPoint(ri, 0, 0, lca)
        b = g.addPoint(ro, 0, 0, lcb)
        c = g.addPoint(ro * math.cos(span), ro * math.sin(span), 0, lc)
        d = g.addPoint(ri * math.cos(span), ri * math.sin(span), 0, lc)
        l1 = g.addLine(a, b)
        arc_out = g.addCircleArc(b, o, c)
        l2 = g.addLine(c, d)
        arc_in = g.addCircleArc(d, o, a)
        s = g.addPlaneSurface([g.addCurveLoop([l1, arc_out, l2, arc_in])])
        return s, [arc_in], [arc_out], [l1], [l2]

    s1, bore, f1, a1, b1 = ring(radii[0], radii[1], True)
    s2, f2, surf, a2, b2 = ring(radii[1], radii[2], False)
    g.synchronize()
    gmsh.model.addPhysicalGroup(2, [s1], name="inner")
    gmsh.model.addPhysicalGroup(2, [s2], name="outer")
    gmsh.model.addPhysicalGroup(1, bore, name="bore")
    gmsh.model.addPhysicalGroup(1, f1, name="inner_face")
    gmsh.model.addPhysicalGroup(1, f2, name="outer_face")
    gmsh.model.addPhysicalGroup(1, surf, name="surface")
    if span is not None:
        gmsh.model.addPhysicalGroup(1, a1 + a2, name="start")
        gmsh.model.addPhysicalGroup(1, b1 + b2, name="end")
    gmsh.model.mesh.generate(2)
    if order == 2:
        gmsh.model.mesh.setOrder(2)

    def curve_points(curves):
        pts = []
        for c in curves:
            t, x, _ = gmsh.model.mesh.getNodes(1, c, includeBoundary=True)
            pts += [(x[3 * i], x[3 * i + 1]) for i in range(len(t))]
        return pts

    p1, p2 = curve_points(f1), curve_points(f2)
    facing = max(min(math.hypot(p[0] - q[0], p[1] - q[1]) for q in p2) for p in p1)
    tags, _, _ = gmsh.model.mesh.getNodes()
    types, elems, _ = gmsh.model.mesh.getElements(2)
    n_tri = sum(len(e) for e in elems)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.write(name + ".msh")
    gmsh.model.remove()
    return {"nodes": len(tags), "triangles": n_tri, "max_facing_distance": facing}


MIXED = """$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
1
2 1 "plate"
$EndPhysicalNames
$Entities
0 0 1 0
1 0 0 0 2 1 0 1 1 0
$EndEntities
$Nodes
1 7 1 7
2 1 0 7
1
2
3
4
5
6
7
0 0 0
1 0 0
0 1 0
0.5 0 0
0.5 0.5 0
0 0.5 0
1 1 0
$EndNodes
$Elements
2 2 1 2
2 1 9 1
1 1 2 3 4 5 6
2 1 2 1
2 2 7 3
$EndElements
"""


def ring_meshes():
    ref = {}
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    ref["rings_p2"] = ring_pair("rings_p2", [1.0, 1.5, 2.0], 0.3, 2)
    vessel = [0.762, 0.7747, 0.7811]
    span = math.radians(8)
    ref["vessel_sector_lc002"] = ring_pair("vessel_sector_lc002", vessel, 0.002, 1, span, 0.0005)
    ref["vessel_sector_lc002_p2"] = ring_pair(
        "vessel_sector_lc002_p2", vessel, 0.002, 2, math.radians(3), 0.0005
    )
    gmsh.finalize()
    with open("mixed_orders.msh", "w") as f:
        f.write(MIXED)
    with open("rings_reference.json", "w") as f:
        json.dump(ref, f, indent=2)


def write41(name):
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.write(name)


def square(g, x0, y0, w, h, lc):
    p = [g.addPoint(x, y, 0, lc) for (x, y) in [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]]
    ls = [g.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
    return g.addPlaneSurface([g.addCurveLoop(ls)]), ls, p


def diagnostic_meshes():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)

    gmsh.model.add("groups")
    g = gmsh.model.geo
    s, ls, p = square(g, 0, 0, 1, 1, 0.5)
    centre = g.addPoint(0.5, 0.5, 0, 0.5)
    g.synchronize()
    gmsh.model.addPhysicalGroup(2, [s], name="plate")
    gmsh.model.addPhysicalGroup(1, [ls[0]], name="bottom")
    gmsh.model.addPhysicalGroup(1, [ls[0], ls[1]], name="supported")
    gmsh.model.addPhysicalGroup(0, [p[0]], name="corner")
    gmsh.model.addPhysicalGroup(0, [centre], name="centre")
    gmsh.model.addPhysicalGroup(1, [99], name="ghost")
    gmsh.model.addPhysicalGroup(3, [], name="vol")
    gmsh.model.mesh.generate(2)
    write41("groups.msh")
    gmsh.model.remove()

    gmsh.model.add("surface_two_groups")
    g = gmsh.model.geo
    s, ls, p = square(g, 0, 0, 1, 1, 0.5)
    g.synchronize()
    gmsh.model.addPhysicalGroup(2, [s], name="plate")
    gmsh.model.addPhysicalGroup(2, [s], name="steel")
    gmsh.model.mesh.generate(2)
    write41("surface_two_groups.msh")
    gmsh.model.remove()

    gmsh.model.add("unmerged")
    g = gmsh.model.geo
    s1, _, _ = square(g, 0, 0, 1, 1, 0.5)
    s2, _, _ = square(g, 1, 0, 1, 1, 0.5)
    g.synchronize()
    gmsh.model.addPhysicalGroup(2, [s1, s2], name="plate")
    gmsh.model.mesh.generate(2)
    write41("unmerged.msh")
    gmsh.model.remove()

    for name, scale in [("plate_mm.msh", 1.0), ("plate_m.msh", 0.001)]:
        gmsh.model.add("plate")
        g = gmsh.model.geo
        s, ls, p = square(g, 0, 0, 200, 100, 50)
        g.synchronize()
        gmsh.model.addPhysicalGroup(2, [s], name="plate")
        gmsh.model.addPhysicalGroup(1, [ls[3]], name="left")
        gmsh.model.addPhysicalGroup(1, [ls[1]], name="right")
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.ScalingFactor", scale)
        write41(name)
        gmsh.option.setNumber("Mesh.ScalingFactor", 1.0)
        gmsh.model.remove()
    gmsh.finalize()


if sys.argv[1:] == ["rings"]:
    ring_meshes()
elif sys.argv[1:] == ["diagnostics"]:
    diagnostic_meshes()
else:
    linear_meshes()
