// Turek & Hron (2006) FSI benchmark geometry (../shared/reference/benchmarks.md): channel
// [0,2.5]x[0,0.41], rigid cylinder centre (0.2,0.2) radius 0.05 (a hole), elastic flag 0.35x0.02
// attached to it, tip point A = (0.6,0.2). One hex layer of thickness `thickness` in z (pseudo-2-D).
// The flag is a structured (transfinite) block so that its bending is resolved through the
// thickness; the fluid is an unstructured all-quad mesh, conforming with the flag.
// Parameters (gmsh -setnumber NAME VALUE): refine (1 = coarse; element sizes scale with 1/refine),
// thickness.
SetFactory("Built-in");
If (!Exists(refine))
  refine = 1;
EndIf

xc = 0.2; yc = 0.2; r = 0.05;
xa = xc + Sqrt(r^2 - 0.01^2);  // where the flag's long sides meet the circle
h_near = 0.024 / refine;  // on the cylinder and the flag (halved by the subdivision)
h_far = 0.1 / refine;     // at the channel walls and the outflow
h_wake = 0.04 / refine;   // behind the flag

Point(1) = {0, 0, 0, h_far};
Point(2) = {2.5, 0, 0, h_far};
Point(3) = {2.5, 0.41, 0, h_far};
Point(4) = {0, 0.41, 0, h_far};
Point(5) = {xc, yc, 0, h_near};         // centre
Point(6) = {xa, 0.19, 0, h_near};       // flag root, lower
Point(7) = {xa, 0.21, 0, h_near};       // flag root, upper
Point(8) = {0.6, 0.19, 0, h_near};      // flag tip, lower
Point(9) = {0.6, 0.21, 0, h_near};      // flag tip, upper
Point(10) = {xc, yc + r, 0, h_near};    // top of the cylinder
Point(11) = {xc - r, yc, 0, h_near};    // front
Point(12) = {xc, yc - r, 0, h_near};    // bottom

Line(1) = {1, 2};  // bottom wall
Line(2) = {2, 3};  // outflow
Line(3) = {3, 4};  // top wall
Line(4) = {4, 1};  // inflow
Circle(5) = {7, 5, 10};
Circle(6) = {10, 5, 11};
Circle(7) = {11, 5, 12};
Circle(8) = {12, 5, 6};
Line(9) = {6, 8};    // flag, lower side
Line(10) = {8, 9};   // flag tip
Line(11) = {9, 7};   // flag, upper side
Circle(12) = {6, 5, 7};  // flag root on the cylinder (clamped)

n_long = Ceil(0.35 / h_near) + 1;
n_thick = Ceil(2 * refine) + 1;  // through the flag: 2 * refine elements, 4 * refine after subdivision
Transfinite Curve{9, 11} = n_long;
Transfinite Curve{10, 12} = n_thick;

Curve Loop(1) = {9, 10, 11, -12};
Plane Surface(1) = {1};  // flag
Transfinite Surface{1};
Recombine Surface{1};

Curve Loop(2) = {1, 2, 3, 4};
Curve Loop(3) = {5, 6, 7, 8, 9, 10, 11};
Plane Surface(2) = {2, 3};  // fluid
Recombine Surface{2};

// Finer elements in the wake, coarser towards the walls and outflow.
Field[1] = Distance;
Field[1].CurvesList = {5, 6, 7, 8, 9, 10, 11};
Field[1].NumPointsPerCurve = 100;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_near;
Field[2].SizeMax = h_far;
Field[2].DistMin = 0.01;
Field[2].DistMax = 0.3;
Field[3] = Box;
Field[3].VIn = h_wake;
Field[3].VOut = h_far;
Field[3].XMin = 0.6; Field[3].XMax = 1.5; Field[3].YMin = 0.1; Field[3].YMax = 0.31;
Field[4] = Min;
Field[4].FieldsList = {2, 3};
Background Field = 4;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;               // frontal-Delaunay (8, for quads, crashes gmsh 4.8)
Mesh.RecombinationAlgorithm = 1;  // blossom
// Every triangle left by the recombination and every quad split in four: all quads, half the
// size set above (full-quad blossom needs even boundary divisions and fails on these curves).
Mesh.SubdivisionAlgorithm = 1;
Mesh.ElementOrder = 1;

// A 2-D quadrilateral mesh: biofsi's reader extrudes it into one layer of hexahedra (the scene or
// the test chooses the thickness), physical surfaces becoming blocks and physical curves boundaries.
Physical Surface("solid") = {1};
Physical Surface("fluid") = {2};
Physical Curve("solid_clamp") = {12};
Physical Curve("fsi") = {9, 10, 11};
Physical Curve("walls") = {1, 3};
Physical Curve("outflow") = {2};
Physical Curve("inflow") = {4};
Physical Curve("cylinder") = {5, 6, 7, 8};
