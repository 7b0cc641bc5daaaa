// A quarter of a 2 x 2 m plate with a central hole of radius 0.1 m (tests/scenes/kirsch), the hole
// at the origin; symmetry sides "left" (x = 0) and "bottom" (y = 0), loaded side "right" (x = 1).
// Meshes (Gmsh 4.8.4), from this folder:
//   gmsh -2 -order 2 -format msh41 plate_hole.geo -o plate_hole_tri6.msh
//   gmsh -2 -order 2 -format msh41 -string "Mesh.RecombineAll=1;Mesh.SecondOrderIncomplete=1;" plate_hole.geo -o plate_hole_quad8.msh
a = 0.1;
lh = 0.01;
lf = 0.12;
Point(1) = {0, 0, 0, lh};
Point(2) = {a, 0, 0, lh};
Point(3) = {1, 0, 0, lf};
Point(4) = {1, 1, 0, lf};
Point(5) = {0, 1, 0, lf};
Point(6) = {0, a, 0, lh};
Line(1) = {2, 3};
Line(2) = {3, 4};
Line(3) = {4, 5};
Line(4) = {5, 6};
Circle(5) = {6, 1, 2};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("left") = {4};
Physical Surface("plate") = {1};
