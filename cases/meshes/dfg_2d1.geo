// DFG / Schaefer-Turek 2D-1 geometry (../shared/reference/benchmarks.md): channel [0,2.2]x[0,0.41],
// cylinder (a hole) of diameter 0.1 centred at (0.2,0.2). One hex layer of thickness `thickness`
// in z (pseudo-2-D). Unstructured all-quad mesh, finest on the cylinder and in the near wake.
// Parameters (gmsh -setnumber NAME VALUE): refine (element sizes scale with 1/refine).
SetFactory("Built-in");
If (!Exists(refine))
  refine = 1;
EndIf

xc = 0.2; yc = 0.2; r = 0.05;
h_near = 0.02 / refine;  // on the cylinder (halved by the subdivision: ~32 elements around it)
h_far = 0.1 / refine;    // at the channel walls and the outflow
h_wake = 0.04 / refine;  // in the near wake

Point(1) = {0, 0, 0, h_far};
Point(2) = {2.2, 0, 0, h_far};
Point(3) = {2.2, 0.41, 0, h_far};
Point(4) = {0, 0.41, 0, h_far};
Point(5) = {xc, yc, 0, h_near};
Point(6) = {xc + r, yc, 0, h_near};
Point(7) = {xc, yc + r, 0, h_near};
Point(8) = {xc - r, yc, 0, h_near};
Point(9) = {xc, yc - r, 0, h_near};

Line(1) = {1, 2};  // bottom wall
Line(2) = {2, 3};  // outflow
Line(3) = {3, 4};  // top wall
Line(4) = {4, 1};  // inflow
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};

Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Recombine Surface{1};

Field[1] = Distance;
Field[1].CurvesList = {5, 6, 7, 8};
Field[1].NumPointsPerCurve = 100;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_near;
Field[2].SizeMax = h_far;
Field[2].DistMin = 0.005;
Field[2].DistMax = 0.3;
Field[3] = Box;
Field[3].VIn = h_wake;
Field[3].VOut = h_far;
Field[3].XMin = 0.2; Field[3].XMax = 1.0; Field[3].YMin = 0.1; Field[3].YMax = 0.31;
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
Physical Surface("fluid") = {1};
Physical Curve("walls") = {1, 3};
Physical Curve("outflow") = {2};
Physical Curve("inflow") = {4};
Physical Curve("cylinder") = {5, 6, 7, 8};
