// A unit cube of 3x3x3 hexahedra in two blocks (x < 1/3 and the rest), for the 3-D path of the
// Gmsh reader. Built-in kernel, transfinite and recombined, extruded in z.
SetFactory("Built-in");
Point(1) = {0, 0, 0}; Point(2) = {1/3, 0, 0}; Point(3) = {1, 0, 0};
Point(4) = {1, 1, 0}; Point(5) = {1/3, 1, 0}; Point(6) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};
Line(6) = {6, 1}; Line(7) = {2, 5};
Curve Loop(1) = {1, 7, 5, 6}; Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, -7}; Plane Surface(2) = {2};
Transfinite Curve{1, 5} = 2; Transfinite Curve{2, 4} = 3; Transfinite Curve{3, 6, 7} = 4;
Transfinite Surface{1, 2}; Recombine Surface{1, 2};
left[] = Extrude {0, 0, 1} { Surface{1}; Layers{3}; Recombine; };
right[] = Extrude {0, 0, 1} { Surface{2}; Layers{3}; Recombine; };
Physical Volume("left") = {left[1]};
Physical Volume("right") = {right[1]};
Physical Surface("x0") = {left[5]};
Physical Surface("x1") = {right[3]};
Physical Surface("cut") = {left[3]};
