// Elastic ring for inputs/ring_impact.dat: outer radius 0.1 m, inner 0.08 m, 4 x 12 x 3 QUAD4.
//   gmsh -2 -format msh41 ring.geo -o ring.msh
R = 0.1; r = 0.08; n = 12; m = 3;
Point(1) = {0, 0, 0};
Point(2) = {R, 0, 0}; Point(3) = {0, R, 0}; Point(4) = {-R, 0, 0}; Point(5) = {0, -R, 0};
Point(6) = {r, 0, 0}; Point(7) = {0, r, 0}; Point(8) = {-r, 0, 0}; Point(9) = {0, -r, 0};
Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 4}; Circle(3) = {4, 1, 5}; Circle(4) = {5, 1, 2};
Circle(5) = {6, 1, 7}; Circle(6) = {7, 1, 8}; Circle(7) = {8, 1, 9}; Circle(8) = {9, 1, 6};
Line(9) = {6, 2}; Line(10) = {7, 3}; Line(11) = {8, 4}; Line(12) = {9, 5};
Curve Loop(1) = {9, 1, -10, -5}; Plane Surface(1) = {1};
Curve Loop(2) = {10, 2, -11, -6}; Plane Surface(2) = {2};
Curve Loop(3) = {11, 3, -12, -7}; Plane Surface(3) = {3};
Curve Loop(4) = {12, 4, -9, -8}; Plane Surface(4) = {4};
Transfinite Curve{1:8} = n + 1;
Transfinite Curve{9:12} = m + 1;
Transfinite Surface{1:4};
Recombine Surface{1:4};
Physical Curve("outer") = {1, 2, 3, 4};
Physical Surface("ring") = {1, 2, 3, 4};
