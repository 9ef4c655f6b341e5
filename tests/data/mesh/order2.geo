// order2.geo: the unit square in second-order (6-node) triangles, which
// peristatic refuses. Regenerate order2.msh with
//   gmsh -2 -order 2 -format msh41 order2.geo -o order2.msh
Point(1) = {0, 0, 0, 0.5};
Point(2) = {1, 0, 0, 0.5};
Point(3) = {1, 1, 0, 0.5};
Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("square") = {1};
