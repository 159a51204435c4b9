#!/usr/bin/env python3
"""Writes the 3-D colony meshes' .geo files: hemisphere.geo and channel3d.geo.

  python3 cases/meshes/colonies3d.py      # rewrites both next to this script

Each colony is a hemisphere on the floor z = 0, meshed as half a cube-sphere: a core half-cube,
five patches from its faces to the sphere (block biofilm) and five from the sphere outward (block
fluid), all transfinite hexahedra, so every sphere node lies on the sphere and the mesh has the
colony's mirror symmetries in x and y. The sphere's edges are great-circle arcs.

hemisphere.geo: one colony of radius 1 in a hemispherical fluid shell out to radius `outer` (the
symmetric growth test). channel3d.geo: colonies in a row along a channel of square section, each
in a box as wide and high as the channel, joined by straight blocks (the channel scene).
The files are Gmsh built-in .geo with the division counts written as expressions in `refine`.
"""

import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
CORNERS = [(sx, sy, sz) for sz in (0, 1) for sy in (-1, 1) for sx in (-1, 1)]
# The five faces of the half cube other than its floor, as (axis, side): x = +-1, y = +-1, z = 1.
SHELL_FACES = [(0, -1), (0, 1), (1, -1), (1, 1), (2, 1)]


class Geo:
    """Points, lines, surfaces and volumes of a built-in .geo, each made once."""

    def __init__(self):
        self.out = []
        self.points = {}  # rounded coordinates -> tag
        self.lines = {}  # (tag, tag) -> (tag, divisions expression, grading)
        self.surfaces = {}  # frozenset of corner tags -> tag
        self.n_volume = 0

    def point(self, p):
        key = tuple(round(c, 12) for c in p)
        if key not in self.points:
            tag = len(self.points) + 1
            self.points[key] = tag
            self.out.append("Point(%d) = {%.15g, %.15g, %.15g};" % ((tag,) + tuple(p)))
        return self.points[key]

    def line(self, a, b, divisions, centre=None, grading=None):
        """The curve from a to b (an arc about centre if given); its signed tag a -> b."""
        if (b, a) in self.lines:
            return -self.lines[(b, a)][0]
        if (a, b) not in self.lines:
            tag = len(self.lines) + 1
            self.lines[(a, b)] = (tag, divisions, grading)
            if centre is None:
                self.out.append("Line(%d) = {%d, %d};" % (tag, a, b))
            else:
                self.out.append("Circle(%d) = {%d, %d, %d};" % (tag, a, centre, b))
        return self.lines[(a, b)][0]

    def surface(self, loop, sphere_centre=None):
        """The quadrilateral over 4 corner tags in order (lines must exist)."""
        key = frozenset(loop)
        if key not in self.surfaces:
            curves = []
            for k in range(4):
                a, b = loop[k], loop[(k + 1) % 4]
                if (a, b) in self.lines:
                    curves.append(self.lines[(a, b)][0])
                else:
                    curves.append(-self.lines[(b, a)][0])
            tag = len(self.surfaces) + 1
            self.surfaces[key] = tag
            self.out.append("Curve Loop(%d) = {%s};" % (tag, ", ".join(map(str, curves))))
            if sphere_centre is None:
                self.out.append("Surface(%d) = {%d};" % (tag, tag))
            else:
                self.out.append("Surface(%d) = {%d} In Sphere {%d};" % (tag, tag, sphere_centre))
        return self.surfaces[key]

    def hexahedron(self, c, spheres=None):
        """The volume over 8 corner tags c[(sx, sy, sz)] with sx, sy, sz in {0, 1}; spheres maps
        a face (axis, side) to the centre tag of the sphere it lies on."""
        tags = []
        for axis in range(3):
            for side in (0, 1):
                corners = [k for k in c if k[axis] == side]
                u, v = [a for a in range(3) if a != axis]
                ring = sorted(corners, key=lambda k: (k[u], k[v]))
                ring = [ring[0], ring[1], ring[3], ring[2]]  # around the face
                centre = (spheres or {}).get((axis, side))
                tags.append(self.surface([c[k] for k in ring], centre))
        self.n_volume += 1
        v = self.n_volume
        self.out.append("Surface Loop(%d) = {%s};" % (v, ", ".join(map(str, tags))))
        self.out.append("Volume(%d) = {%d};" % (v, v))
        order = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
        self.out.append(
            "Transfinite Volume{%d} = {%s};" % (v, ", ".join(str(c[k]) for k in order)))
        return v, tags

    def text(self, header, physicals):
        lines = list(header)
        lines += self.out
        by_count = {}
        for (tag, divisions, grading) in self.lines.values():
            by_count.setdefault((divisions, grading), []).append(tag)
        for (divisions, grading), tags in sorted(by_count.items(), key=lambda kv: kv[1][0]):
            using = "" if grading is None else " Using Progression %s" % grading
            lines.append("Transfinite Curve{%s} = %s + 1%s;" %
                         (", ".join(map(str, sorted(tags))), divisions, using))
        lines.append("Transfinite Surface{:};")
        lines.append("Recombine Surface{:};")
        lines += physicals
        return "\n".join(lines) + "\n"


def unit(p):
    n = math.sqrt(sum(c * c for c in p))
    return [c / n for c in p]


def colony(geo, xc, radius, outer, outer_sphere):
    """One colony at (xc, 0, 0): the core, the inner shell (biofilm) and the outer shell (fluid).
    outer(sx, sy, sz) is the outer corner over (sx, sy, sz); outer_sphere: the outer surface is
    the sphere about the centre. Returns (biofilm volumes, fluid volumes, sphere surfaces, floor
    surfaces, outer surfaces by face) and the outer corner tags."""
    a = 0.45 * radius
    centre = geo.point((xc, 0, 0))
    core = {k: geo.point((xc + k[0] * a, k[1] * a, k[2] * a)) for k in CORNERS}
    sphere = {}
    for k in CORNERS:
        u = unit(k)
        sphere[k] = geo.point((xc + radius * u[0], radius * u[1], radius * u[2]))
    out = {k: geo.point(outer(*k)) for k in CORNERS}

    def divisions(k1, k2):
        return "n_half" if k1[2] != k2[2] else "n_arc"

    for level, arc in ((core, None), (sphere, centre), (out, centre if outer_sphere else None)):
        for k1 in CORNERS:
            for k2 in CORNERS:
                if k1 < k2 and sum(x != y for x, y in zip(k1, k2)) == 1:
                    geo.line(level[k1], level[k2], divisions(k1, k2), arc)
    for k in CORNERS:
        geo.line(core[k], sphere[k], "n_ring")
        geo.line(sphere[k], out[k], "n_fluid", grading="q_fluid")

    def block(inner, outer_level, axis, side, sphere_at_outer, sphere_at_inner):
        # Local corner (i, j, r): r = 0 on the inner level, 1 on the outer; i, j span the face.
        u, v = [t for t in range(3) if t != axis]
        c = {}
        for k in CORNERS:
            if k[axis] != (side if axis < 2 else 1):
                continue
            for r, level in ((0, inner), (1, outer_level)):
                local = [0, 0, 0]
                local[u] = (k[u] + 1) // 2 if u < 2 else k[u]
                local[v] = (k[v] + 1) // 2 if v < 2 else k[v]
                local[axis] = r
                c[tuple(local)] = level[k]
        spheres = {}
        if sphere_at_inner:
            spheres[(axis, 0)] = centre
        if sphere_at_outer:
            spheres[(axis, 1)] = centre
        return geo.hexahedron(c, spheres)

    core_local = {((k[0] + 1) // 2, (k[1] + 1) // 2, k[2]): core[k] for k in CORNERS}
    v_core, core_faces = geo.hexahedron(core_local)
    biofilm, fluid, interface, outer_faces = [v_core], [], [], {}
    floor = [core_faces[4]]
    for axis, side in SHELL_FACES:
        v, faces = block(core, sphere, axis, side, True, False)
        biofilm.append(v)
        interface.append(faces[2 * axis + 1])
        if axis < 2:
            floor.append(faces[4])
        v, faces = block(sphere, out, axis, side, outer_sphere, True)
        fluid.append(v)
        outer_faces[(axis, side)] = faces[2 * axis + 1]
        if axis < 2:
            floor.append(faces[4])
    return biofilm, fluid, interface, floor, outer_faces, out


def physical(kind, name, tags):
    return 'Physical %s("%s") = {%s};' % (kind, name, ", ".join(map(str, tags)))


def parameters(counts):
    """The refine parameter and the division counts (name, expression, comment) it scales."""
    lines = ['SetFactory("Built-in");', "If (!Exists(refine))", "  refine = 1;", "EndIf"]
    for name, value, comment in counts:
        lines.append(("%s = %s;" % (name, value)).ljust(33) + "// " + comment)
    return lines


def colony_physicals(biofilm, fluid, interface, face_sets):
    """Blocks biofilm and fluid, the face set biofilm_fluid and the domain's face sets (a list of
    (name, surfaces))."""
    out = [physical("Volume", "biofilm", biofilm), physical("Volume", "fluid", fluid),
           physical("Surface", "biofilm_fluid", interface)]
    return out + [physical("Surface", name, tags) for name, tags in face_sets]


def hemisphere():
    geo = Geo()
    biofilm, fluid, interface, floor, outer, _ = colony(
        geo, 0.0, 1.0, lambda sx, sy, sz: [3.0 * u for u in unit((sx, sy, sz))], True)
    header = [
        "// A hemispherical colony of radius 1 on the floor z = 0, centred at the origin, in a",
        "// hemispherical fluid shell out to radius 3: half a cube-sphere of transfinite hexahedra",
        "// (a core half-cube, five patches to the sphere, five to the outer sphere). Written by",
        "// colonies3d.py; the growth tests (tests/growth/test_colony3d.cpp) read it.",
        "// Blocks: biofilm, fluid. Face sets: biofilm_fluid (the colony's sphere), outer (the outer",
        "// sphere), floor (z = 0). Parameter (gmsh -setnumber refine R): every count scales with R.",
    ] + parameters([
        ("n_arc", "2 * Round(4 * refine)", "a quarter of the equator, an edge of a patch"),
        ("n_half", "n_arc / 2", "from the equator up to the top patch"),
        ("n_ring", "Round(4 * refine)", "radial, core to sphere"),
        ("n_fluid", "Round(8 * refine)", "radial, sphere to the outer sphere"),
        ("q_fluid", "1.1^(1 / refine)", "element growth away from the colony"),
    ])
    return geo.text(header, colony_physicals(biofilm, fluid, interface,
                                             [("outer", sorted(outer.values())), ("floor", floor)]))


def channel(centres, radii, half_width, height, x_in, x_out):
    geo = Geo()
    biofilm, fluid, interface, floor, walls = [], [], [], [], []
    boxes = []
    for xc, r in zip(centres, radii):
        b, f, i, fl, outer, out = colony(
            geo, xc, r,
            lambda sx, sy, sz, xc=xc: [xc + sx * half_width, sy * half_width, sz * height], False)
        biofilm += b
        fluid += f
        interface += i
        floor += fl
        walls += [outer[(1, -1)], outer[(1, 1)], outer[(2, 1)]]
        boxes.append((outer, out))
    # Straight blocks: inlet to the first box, between boxes, last box to the outlet.
    inlet = {k: geo.point([x_in, k[1] * half_width, k[2] * height]) for k in CORNERS}
    outlet = {k: geo.point([x_out, k[1] * half_width, k[2] * height]) for k in CORNERS}
    faces_at = [(inlet, "n_in")]
    for outer, out in boxes:
        faces_at.append((out, None))
    faces_at.append((outlet, "n_out"))
    ends = []
    for j in range(len(faces_at) - 1):
        left, right = faces_at[j][0], faces_at[j + 1][0]
        count = faces_at[j][1] or faces_at[j + 1][1] or "n_gap"
        c = {}
        for k in CORNERS:
            lk, rk = (1, k[1], k[2]), (-1, k[1], k[2])
            c[(0, (k[1] + 1) // 2, k[2])] = left[lk]
            c[(1, (k[1] + 1) // 2, k[2])] = right[rk]
        # The inlet's and outlet's faces need their lines; a box's exist already.
        for level in (left, right):
            for k1 in CORNERS:
                for k2 in CORNERS:
                    if k1 < k2 and sum(x != y for x, y in zip(k1, k2)) == 1 and k1[0] == k2[0]:
                        geo.line(level[k1], level[k2], "n_half" if k1[2] != k2[2] else "n_arc")
        for sy in (-1, 1):
            for sz in (0, 1):
                geo.line(left[(1, sy, sz)], right[(-1, sy, sz)], count)
        v, faces = geo.hexahedron(c)
        fluid.append(v)
        floor.append(faces[4])
        walls += [faces[2], faces[3], faces[5]]
        if j == 0:
            ends.append(faces[0])
        if j == len(faces_at) - 2:
            ends.append(faces[1])
    header = [
        "// Hemispherical colonies on the floor of a 3-D channel (cases/colonies/channel3d.yaml):",
        "// the channel x in [%g, %g], y in [%g, %g], z in [0, %g]; colonies of radii %s centred on"
        % (x_in, x_out, -half_width, half_width, height, ", ".join("%g" % r for r in radii)),
        "// the floor at x = %s. Each colony is half a cube-sphere of transfinite hexahedra in a box"
        % ", ".join("%g" % x for x in centres),
        "// as wide and high as the channel; straight blocks join the boxes. Written by",
        "// colonies3d.py. Blocks: biofilm, fluid. Face sets: biofilm_fluid (the colonies'",
        "// spheres), floor (z = 0), walls (y = +-%g and z = %g), inflow (x = %g), outflow (x = %g)."
        % (half_width, height, x_in, x_out),
        "// Parameter (gmsh -setnumber refine R): every count scales with R.",
    ] + parameters([
        ("n_arc", "2 * Round(2 * refine)", "a quarter of a colony's equator, a side of its box"),
        ("n_half", "n_arc / 2", "from the equator up to the top patch"),
        ("n_ring", "Round(2 * refine)", "radial, core to sphere"),
        ("n_fluid", "Round(3 * refine)", "sphere to box"),
        ("q_fluid", "1.15^(1 / refine)", "element growth away from the colony"),
        ("n_gap", "Round(2 * refine)", "between two boxes"),
        ("n_in", "Round(3 * refine)", "inlet to the first box"),
        ("n_out", "Round(6 * refine)", "last box to the outlet"),
    ])
    return geo.text(header, colony_physicals(
        biofilm, fluid, interface,
        [("floor", floor), ("walls", walls), ("inflow", [ends[0]]), ("outflow", [ends[1]])]))


if __name__ == "__main__":
    with open(os.path.join(HERE, "hemisphere.geo"), "w") as f:
        f.write(hemisphere())
    with open(os.path.join(HERE, "channel3d.geo"), "w") as f:
        f.write(channel([0.0, 5.0, 10.0], [1.0, 0.7, 1.0], 2.0, 2.0, -4.0, 20.0))
