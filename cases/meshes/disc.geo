// A circular biofilm colony of radius 1 centred at the origin in the fluid square
// [-half, half]^2 (the colony scenes, ../colonies/disc.yaml). One hex layer in z when the scene
// extrudes it (pseudo-2-D).
//
// Block-structured all-quad O-grid of transfinite patches: a square core [-a, a]^2 of the colony,
// four patches from the core to the circle, four from the circle to the square's sides (graded
// away from the colony). Every quarter of the circle has the same number of equal arcs, so the
// discrete interface is a regular polygon and its nodal normals are radial.
// Blocks (physical surfaces): biofilm, fluid. Face sets (physical curves): biofilm_fluid (the
// circle), outer (the square's sides).
// Parameters (gmsh -setnumber NAME VALUE): refine (every division count scales with it), half.
SetFactory("Built-in");
If (!Exists(refine))
  refine = 1;
EndIf
If (!Exists(half))
  half = 3;
EndIf

a = 0.45;                      // half-width of the colony's core square
n_arc = Round(8 * refine);     // a quarter of the circle, a side of the core and of the square
n_ring = Round(4 * refine);    // radial, core to circle
n_fluid = Round(8 * refine);   // radial, circle to the square's sides
q_fluid = 1.15^(1 / refine);   // element growth away from the colony
c = 1 / Sqrt(2);

Point(1) = {0, 0, 0};
Point(2) = {a, a, 0};     Point(3) = {-a, a, 0};     Point(4) = {-a, -a, 0};     Point(5) = {a, -a, 0};
Point(6) = {c, c, 0};     Point(7) = {-c, c, 0};     Point(8) = {-c, -c, 0};     Point(9) = {c, -c, 0};
Point(10) = {half, half, 0};  Point(11) = {-half, half, 0};
Point(12) = {-half, -half, 0};  Point(13) = {half, -half, 0};

// Core square, circle arcs, outer square: counter-clockwise from the NE corner.
Line(1) = {2, 3};  Line(2) = {3, 4};  Line(3) = {4, 5};  Line(4) = {5, 2};
Circle(5) = {6, 1, 7};  Circle(6) = {7, 1, 8};  Circle(7) = {8, 1, 9};  Circle(8) = {9, 1, 6};
Line(9) = {10, 11};  Line(10) = {11, 12};  Line(11) = {12, 13};  Line(12) = {13, 10};
// Radial lines: core corner to circle, circle to square corner.
Line(13) = {2, 6};  Line(14) = {3, 7};  Line(15) = {4, 8};  Line(16) = {5, 9};
Line(17) = {6, 10};  Line(18) = {7, 11};  Line(19) = {8, 12};  Line(20) = {9, 13};

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {13, 5, -14, -1};   Plane Surface(2) = {2};
Curve Loop(3) = {14, 6, -15, -2};   Plane Surface(3) = {3};
Curve Loop(4) = {15, 7, -16, -3};   Plane Surface(4) = {4};
Curve Loop(5) = {16, 8, -13, -4};   Plane Surface(5) = {5};
Curve Loop(6) = {17, 9, -18, -5};   Plane Surface(6) = {6};
Curve Loop(7) = {18, 10, -19, -6};  Plane Surface(7) = {7};
Curve Loop(8) = {19, 11, -20, -7};  Plane Surface(8) = {8};
Curve Loop(9) = {20, 12, -17, -8};  Plane Surface(9) = {9};

Transfinite Curve{1:12} = n_arc + 1;
Transfinite Curve{13:16} = n_ring + 1;
Transfinite Curve{17:20} = n_fluid + 1 Using Progression q_fluid;
Transfinite Surface{1:9};
Recombine Surface{1:9};

Physical Surface("biofilm") = {1:5};
Physical Surface("fluid") = {6:9};
Physical Curve("biofilm_fluid") = {5:8};
Physical Curve("outer") = {9:12};
