// plate.geo: a 20 mm x 10 mm plate in 20 x 10 structured quadrangles of
// 1 mm, its sides as physical curves: the mesh of the box case
// geometry: {type: box, counts: [20, 10], spacing: 1.0e-3} (element
// centroids = the box's lattice). Regenerate plate.msh with
//   gmsh -2 -format msh41 plate.geo -o plate.msh
Point(1) = {0, 0, 0};
Point(2) = {0.02, 0, 0};
Point(3) = {0.02, 0.01, 0};
Point(4) = {0, 0.01, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 21;
Transfinite Curve{2, 4} = 11;
Transfinite Surface{1};
Recombine Surface{1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Surface("plate") = {1};
