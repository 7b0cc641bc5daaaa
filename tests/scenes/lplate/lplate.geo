// L-shaped plate for tests/scenes/lplate: 2 x 2 m with the upper right 1 x 1 m removed.
// Meshes (Gmsh 4.8.4), from this folder:
//   gmsh -2 -order 2 -format msh22 lplate.geo -o lplate_tri6_v22.msh
//   gmsh -2 -order 2 -format msh41 lplate.geo -o lplate_tri6_v41.msh
//   gmsh -2 -order 2 -format msh41 -bin lplate.geo -o lplate_tri6_bin.msh
//   gmsh -2 -order 1 -format msh41 lplate.geo -o lplate_tri3.msh
//   gmsh -2 -order 2 -format msh41 -string "Mesh.RecombineAll=1;Mesh.SecondOrderIncomplete=1;" lplate.geo -o lplate_quad8.msh
lc = 0.25;
Point(1) = {0, 0, 0, lc};
Point(2) = {2, 0, 0, lc};
Point(3) = {2, 1, 0, lc};
Point(4) = {1, 1, 0, lc};
Point(5) = {1, 2, 0, lc};
Point(6) = {0, 2, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("top") = {5};
Physical Surface("plate") = {1};
Physical Point("corner") = {6};
