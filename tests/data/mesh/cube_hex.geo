// cube_hex.geo: the unit cube, 3 x 3 x 3 structured hexahedra, with its
// top face as a physical surface. Regenerate cube_hex.msh with
//   gmsh -3 -format msh41 cube_hex.geo -o cube_hex.msh
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 1, 0};
Point(4) = {0, 1, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 4;
Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {0, 0, 1} { Surface{1}; Layers{3}; Recombine; };
Physical Surface("top") = {out[0]};
Physical Volume("cube") = {out[1]};
