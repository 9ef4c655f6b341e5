// plate-gmsh.geo: a 20 mm x 10 mm plate with a central hole of radius
// 2 mm, meshed with quadrangles of about 0.5 mm (Gmsh's recombination of
// a triangle mesh), its four sides and the hole's edge as physical curves
// for data/cases/plate-gmsh.yaml. Regenerate plate-gmsh.msh with
//   gmsh -2 -format msh41 plate-gmsh.geo -o plate-gmsh.msh
lc = 0.0005;
Point(1) = {0, 0, 0, lc};
Point(2) = {0.02, 0, 0, lc};
Point(3) = {0.02, 0.01, 0, lc};
Point(4) = {0, 0.01, 0, lc};
Point(5) = {0.01, 0.005, 0, lc};
Point(6) = {0.012, 0.005, 0, lc};
Point(7) = {0.01, 0.007, 0, lc};
Point(8) = {0.008, 0.005, 0, lc};
Point(9) = {0.01, 0.003, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Recombine Surface{1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Curve("hole") = {5, 6, 7, 8};
Physical Surface("plate") = {1};
