// DFG / Schaefer-Turek 2D-1 geometry (../shared/reference/benchmarks.md): channel [0,2.2]x[0,0.41],
// cylinder (a hole) of diameter 0.1 centred at (0.2,0.2). One hex layer of thickness `thickness`
// in z (pseudo-2-D).
//
// Block-structured all-quad mesh (12 transfinite patches): an O-grid ring between the cylinder and
// the box [0.1,0.3]^2, graded towards the cylinder, channel patches around it and a wake that
// coarsens downstream; the same layout as turek_hron.geo without the flag. Why structured: on an
// unstructured blossom mesh the lift is +26% off at refine 2 and swings by +-20% with the
// grad-div parameter, the distorted quads that subdividing triangles leaves polluting the
// discrete mass balance that the small lift (c_L/c_D ~ 2e-3) depends on.
// Parameters (gmsh -setnumber NAME VALUE): refine (every division count scales with refine, every
// grading ratio with its refine-th root).
SetFactory("Built-in");
If (!Exists(refine))
  refine = 1;
EndIf

xc = 0.2; yc = 0.2; r = 0.05;
s = r / Sqrt(2);

n_up = Round(4 * refine);     // x in [0, 0.1]
n_box = Round(12 * refine);   // a box side and the quarter of the cylinder facing it
n_wake = Round(50 * refine);  // x in [0.3, 2.2]
n_wall = Round(5 * refine);   // y in [0, 0.1] and [0.3, 0.41]
n_ring = Round(10 * refine);  // radial, cylinder to box
q_ring = 1.12^(1 / refine);   // element growth away from the cylinder
q_wake = 1.04^(1 / refine);   // downstream

Point(1) = {0, 0, 0};     Point(2) = {0.1, 0, 0};     Point(3) = {0.3, 0, 0};    Point(4) = {2.2, 0, 0};
Point(5) = {0, 0.1, 0};   Point(6) = {0.1, 0.1, 0};   Point(7) = {0.3, 0.1, 0};  Point(8) = {2.2, 0.1, 0};
Point(9) = {0, 0.3, 0};   Point(10) = {0.1, 0.3, 0};  Point(11) = {0.3, 0.3, 0}; Point(12) = {2.2, 0.3, 0};
Point(13) = {0, 0.41, 0}; Point(14) = {0.1, 0.41, 0}; Point(15) = {0.3, 0.41, 0};
Point(16) = {2.2, 0.41, 0};
Point(20) = {xc, yc, 0};
Point(21) = {xc + s, yc + s, 0};  Point(22) = {xc - s, yc + s, 0};  // NE, NW
Point(23) = {xc - s, yc - s, 0};  Point(24) = {xc + s, yc - s, 0};  // SW, SE

Line(1) = {1, 2};   Line(2) = {2, 3};   Line(3) = {3, 4};
Line(4) = {5, 6};   Line(5) = {6, 7};   Line(6) = {7, 8};
Line(7) = {9, 10};  Line(8) = {10, 11}; Line(9) = {11, 12};
Line(10) = {13, 14}; Line(11) = {14, 15}; Line(12) = {15, 16};
Line(21) = {1, 5};  Line(22) = {5, 9};  Line(23) = {9, 13};
Line(24) = {2, 6};  Line(25) = {6, 10}; Line(26) = {10, 14};
Line(27) = {3, 7};  Line(28) = {7, 11}; Line(29) = {11, 15};
Line(30) = {4, 8};  Line(31) = {8, 12}; Line(32) = {12, 16};
Line(41) = {21, 11}; Line(42) = {22, 10}; Line(43) = {23, 6}; Line(44) = {24, 7};
Circle(51) = {24, 20, 21}; Circle(52) = {21, 20, 22}; Circle(53) = {22, 20, 23};
Circle(54) = {23, 20, 24};

Transfinite Curve{1, 4, 7, 10} = n_up + 1;
Transfinite Curve{2, 5, 8, 11, 22, 25, 28, 31, 51, 52, 53, 54} = n_box + 1;
Transfinite Curve{3, 6, 9, 12} = n_wake + 1 Using Progression q_wake;
Transfinite Curve{21, 24, 27, 30, 23, 26, 29, 32} = n_wall + 1;
Transfinite Curve{41, 42, 43, 44} = n_ring + 1 Using Progression q_ring;

Curve Loop(1) = {1, 24, -4, -21};   Plane Surface(1) = {1};
Curve Loop(2) = {2, 27, -5, -24};   Plane Surface(2) = {2};
Curve Loop(3) = {3, 30, -6, -27};   Plane Surface(3) = {3};
Curve Loop(4) = {4, 25, -7, -22};   Plane Surface(4) = {4};
Curve Loop(5) = {6, 31, -9, -28};   Plane Surface(5) = {5};   // wake
Curve Loop(6) = {7, 26, -10, -23};  Plane Surface(6) = {6};
Curve Loop(7) = {8, 29, -11, -26};  Plane Surface(7) = {7};
Curve Loop(8) = {9, 32, -12, -29};  Plane Surface(8) = {8};
Curve Loop(9) = {51, 41, -28, -44}; Plane Surface(9) = {9};   // ring, right
Curve Loop(10) = {52, 42, 8, -41};  Plane Surface(10) = {10}; // ring, top
Curve Loop(11) = {53, 43, 25, -42}; Plane Surface(11) = {11}; // ring, left
Curve Loop(12) = {54, 44, -5, -43}; Plane Surface(12) = {12}; // ring, bottom

Transfinite Surface{1:12};
Recombine Surface{1:12};
Mesh.ElementOrder = 1;

// A 2-D quadrilateral mesh: biofsi's reader extrudes it into one layer of hexahedra (the scene or
// the test chooses the thickness), physical surfaces becoming blocks and physical curves boundaries.
Physical Surface("fluid") = {1:12};
Physical Curve("walls") = {1, 2, 3, 10, 11, 12};
Physical Curve("outflow") = {30, 31, 32};
Physical Curve("inflow") = {21, 22, 23};
Physical Curve("cylinder") = {51, 52, 53, 54};
