// cube_tet.geo: the unit cube in unstructured tetrahedra (a few hundred).
// Regenerate cube_tet.msh with
//   gmsh -3 -format msh41 cube_tet.geo -o cube_tet.msh
SetFactory("Built-in");
lc = 0.3;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, 1} { Surface{1}; };
Physical Surface("top") = {out[0]};
Physical Volume("cube") = {out[1]};
