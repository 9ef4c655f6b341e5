// square_tri.geo: the unit square in unstructured triangles (about 60),
// with two physical surfaces (blocks 7 and 9: x < 0.4 and x > 0.4) and
// the top side as a physical curve. Regenerate square_tri.msh with
//   gmsh -2 -format msh41 square_tri.geo -o square_tri.msh
lc = 0.2;
Point(1) = {0, 0, 0, lc};
Point(2) = {0.4, 0, 0, lc};
Point(3) = {1, 0, 0, lc};
Point(4) = {1, 1, 0, lc};
Point(5) = {0.4, 1, 0, lc};
Point(6) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {2, 5};
Curve Loop(1) = {1, 7, 5, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, -7};
Plane Surface(2) = {2};
Physical Curve("top") = {4, 5};
Physical Surface("left part", 7) = {1};
Physical Surface("right part", 9) = {2};
