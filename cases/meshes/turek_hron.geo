// Turek & Hron (2006) FSI benchmark geometry (../shared/reference/benchmarks.md): channel
// [0,2.5]x[0,0.41], rigid cylinder centre (0.2,0.2) radius 0.05 (a hole), elastic flag 0.35x0.02
// attached to it, tip point A = (0.6,0.2). One hex layer of thickness `thickness` in z (pseudo-2-D).
//
// Block-structured all-quad mesh (21 transfinite patches): an O-grid ring between the cylinder and
// the box [0.1,0.3]^2, graded towards the cylinder; the flag in two patches (root inside the ring,
// the rest outside), with the fluid rows next to it graded towards it; channel patches around, and
// a wake that coarsens downstream. Why structured: on an unstructured blossom mesh the lift
// converges slowly (CFD1 +7.8% at refine 2, +5.1% at refine 4), the Q1-Q1 solution being
// sensitive to the distorted quads that subdividing triangles leaves.
// Parameters (gmsh -setnumber NAME VALUE): refine (1 = coarse; every division count scales with
// refine, every grading ratio with its refine-th root, so that the meshes are nested in shape);
// c_up, c_box, c_flag, c_wake, c_wall, c_side, c_thick, c_ring (divisions at refine 1) and g_ring,
// g_side, g_wake (grading ratios at refine 1) override the defaults below, for mesh studies
// (tests/coupling/test_fsi_benchmarks.cpp records one); the defaults give the meshes the tests use.
SetFactory("Built-in");
If (!Exists(refine))
  refine = 1;
EndIf

xc = 0.2; yc = 0.2; r = 0.05;
xa = xc + Sqrt(r^2 - 0.01^2);  // where the flag's long sides meet the circle
s = r / Sqrt(2);

// Divisions (elements) per patch edge at refine 1, and grading ratios; each can be overridden
// (-setnumber) for mesh studies.
If (!Exists(c_up)) c_up = 4; EndIf
If (!Exists(c_box)) c_box = 10; EndIf
If (!Exists(c_flag)) c_flag = 40; EndIf
If (!Exists(c_wake)) c_wake = 50; EndIf
If (!Exists(c_wall)) c_wall = 5; EndIf
If (!Exists(c_side)) c_side = 6; EndIf
If (!Exists(c_thick)) c_thick = 2; EndIf
If (!Exists(c_ring)) c_ring = 8; EndIf
If (!Exists(g_ring)) g_ring = 1.1; EndIf
If (!Exists(g_side)) g_side = 1.2; EndIf
If (!Exists(g_wake)) g_wake = 1.04; EndIf
n_up = Round(c_up * refine);     // x in [0, 0.1]
n_box = Round(c_box * refine);   // a box side [0.1, 0.3] and the 90-degree arcs facing it
n_flag = Round(c_flag * refine);  // x in [0.3, 0.6], along the flag and the fluid above and below it
n_wake = Round(c_wake * refine);  // x in [0.6, 2.5]
n_wall = Round(c_wall * refine);   // y in [0, 0.1] and [0.3, 0.41]
n_side = Round(c_side * refine);   // y in [0.1, 0.19] and [0.21, 0.3], and the arcs between flag and box corner
n_thick = 2 * Round(c_thick * refine);  // through the flag (even: point A is a node)
n_ring = Round(c_ring * refine);   // radial, cylinder to box (and the flag's root patch)
q_ring = g_ring^(1 / refine);   // element growth away from the cylinder
q_side = g_side^(1 / refine);   // away from the flag
q_wake = g_wake^(1 / refine);  // downstream

Point(1) = {0, 0, 0};      Point(2) = {0.1, 0, 0};    Point(3) = {0.3, 0, 0};
Point(4) = {0.6, 0, 0};    Point(5) = {2.5, 0, 0};
Point(6) = {0, 0.1, 0};    Point(7) = {0.1, 0.1, 0};  Point(8) = {0.3, 0.1, 0};
Point(9) = {0.6, 0.1, 0};  Point(10) = {2.5, 0.1, 0};
Point(11) = {0.3, 0.19, 0}; Point(12) = {0.6, 0.19, 0}; Point(13) = {2.5, 0.19, 0};
Point(14) = {0.3, 0.21, 0}; Point(15) = {0.6, 0.21, 0}; Point(16) = {2.5, 0.21, 0};
Point(17) = {0, 0.3, 0};   Point(18) = {0.1, 0.3, 0}; Point(19) = {0.3, 0.3, 0};
Point(20) = {0.6, 0.3, 0}; Point(21) = {2.5, 0.3, 0};
Point(22) = {0, 0.41, 0};  Point(23) = {0.1, 0.41, 0}; Point(24) = {0.3, 0.41, 0};
Point(25) = {0.6, 0.41, 0}; Point(26) = {2.5, 0.41, 0};
Point(30) = {xc, yc, 0};                                    // centre
Point(31) = {xc + s, yc + s, 0};  Point(32) = {xc - s, yc + s, 0};  // NE, NW
Point(33) = {xc - s, yc - s, 0};  Point(34) = {xc + s, yc - s, 0};  // SW, SE
Point(35) = {xa, 0.19, 0};  Point(36) = {xa, 0.21, 0};      // flag root, lower and upper

// Horizontal lines (left to right).
Line(1) = {1, 2};   Line(2) = {2, 3};   Line(3) = {3, 4};   Line(4) = {4, 5};
Line(5) = {6, 7};   Line(6) = {7, 8};   Line(7) = {8, 9};   Line(8) = {9, 10};
Line(9) = {35, 11}; Line(10) = {11, 12}; Line(11) = {12, 13};
Line(12) = {36, 14}; Line(13) = {14, 15}; Line(14) = {15, 16};
Line(15) = {17, 18}; Line(16) = {18, 19}; Line(17) = {19, 20}; Line(18) = {20, 21};
Line(19) = {22, 23}; Line(20) = {23, 24}; Line(21) = {24, 25}; Line(22) = {25, 26};
// Vertical lines (bottom to top).
Line(31) = {1, 6};   Line(32) = {6, 17};  Line(33) = {17, 22};
Line(34) = {2, 7};   Line(35) = {7, 18};  Line(36) = {18, 23};
Line(37) = {3, 8};   Line(38) = {8, 11};  Line(39) = {11, 14}; Line(40) = {14, 19};
Line(41) = {19, 24};
Line(42) = {4, 9};   Line(43) = {9, 12};  Line(44) = {12, 15}; Line(45) = {15, 20};
Line(46) = {20, 25};
Line(47) = {5, 10};  Line(48) = {10, 13}; Line(49) = {13, 16}; Line(50) = {16, 21};
Line(51) = {21, 26};
// Radial lines of the ring, cylinder to box corner.
Line(61) = {31, 19}; Line(62) = {32, 18}; Line(63) = {33, 7}; Line(64) = {34, 8};
// Arcs of the cylinder (counter-clockwise) and the clamped flag root.
Circle(71) = {36, 30, 31}; Circle(72) = {31, 30, 32}; Circle(73) = {32, 30, 33};
Circle(74) = {33, 30, 34}; Circle(75) = {34, 30, 35}; Circle(76) = {35, 30, 36};

Transfinite Curve{1, 5, 15, 19} = n_up + 1;
Transfinite Curve{2, 6, 16, 20, 35, 32, 72, 73, 74} = n_box + 1;
Transfinite Curve{3, 7, 10, 13, 17, 21} = n_flag + 1;
Transfinite Curve{4, 8, 11, 14, 18, 22} = n_wake + 1 Using Progression q_wake;
Transfinite Curve{31, 34, 37, 42, 47, 33, 36, 41, 46, 51} = n_wall + 1;
Transfinite Curve{38, 43, 48} = n_side + 1 Using Progression 1 / q_side;  // fine at y = 0.19
Transfinite Curve{40, 45, 50} = n_side + 1 Using Progression q_side;      // fine at y = 0.21
Transfinite Curve{75} = n_side + 1 Using Progression 1 / q_side;          // fine at the flag
Transfinite Curve{71} = n_side + 1 Using Progression q_side;
Transfinite Curve{39, 44, 49, 76} = n_thick + 1;
Transfinite Curve{61, 62, 63, 64, 9, 12} = n_ring + 1 Using Progression q_ring;

Curve Loop(1) = {1, 34, -5, -31};     Plane Surface(1) = {1};
Curve Loop(2) = {2, 37, -6, -34};     Plane Surface(2) = {2};
Curve Loop(3) = {3, 42, -7, -37};     Plane Surface(3) = {3};
Curve Loop(4) = {4, 47, -8, -42};     Plane Surface(4) = {4};
Curve Loop(5) = {5, 35, -15, -32};    Plane Surface(5) = {5};
Curve Loop(6) = {15, 36, -19, -33};   Plane Surface(6) = {6};
Curve Loop(7) = {16, 41, -20, -36};   Plane Surface(7) = {7};
Curve Loop(8) = {17, 46, -21, -41};   Plane Surface(8) = {8};
Curve Loop(9) = {18, 51, -22, -46};   Plane Surface(9) = {9};
Curve Loop(10) = {72, 62, 16, -61};   Plane Surface(10) = {10};  // ring, top
Curve Loop(11) = {73, 63, 35, -62};   Plane Surface(11) = {11};  // ring, left
Curve Loop(12) = {74, 64, -6, -63};   Plane Surface(12) = {12};  // ring, bottom
Curve Loop(13) = {75, 9, -38, -64};   Plane Surface(13) = {13};  // ring, below the flag root
Curve Loop(14) = {71, 61, -40, -12};  Plane Surface(14) = {14};  // ring, above the flag root
Curve Loop(15) = {7, 43, -10, -38};   Plane Surface(15) = {15};  // below the flag
Curve Loop(16) = {13, 45, -17, -40};  Plane Surface(16) = {16};  // above the flag
Curve Loop(17) = {8, 48, -11, -43};   Plane Surface(17) = {17};  // wake
Curve Loop(18) = {11, 49, -14, -44};  Plane Surface(18) = {18};
Curve Loop(19) = {14, 50, -18, -45};  Plane Surface(19) = {19};
Curve Loop(20) = {9, 39, -12, -76};   Plane Surface(20) = {20};  // flag root (solid)
Curve Loop(21) = {10, 44, -13, -39};  Plane Surface(21) = {21};  // flag (solid)

Transfinite Surface{1:21};
Recombine Surface{1:21};
Mesh.ElementOrder = 1;

// A 2-D quadrilateral mesh: biofsi's reader extrudes it into one layer of hexahedra (the scene or
// the test chooses the thickness), physical surfaces becoming blocks and physical curves boundaries.
Physical Surface("solid") = {20, 21};
Physical Surface("fluid") = {1:19};
Physical Curve("solid_clamp") = {76};
Physical Curve("fsi") = {9, 10, 44, 13, 12};
Physical Curve("walls") = {1, 2, 3, 4, 19, 20, 21, 22};
Physical Curve("outflow") = {47, 48, 49, 50, 51};
Physical Curve("inflow") = {31, 32, 33};
Physical Curve("cylinder") = {71, 72, 73, 74, 75};
