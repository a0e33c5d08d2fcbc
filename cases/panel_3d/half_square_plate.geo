// Shell mid-surface of the 3-D Euler panel case (half model): the half of square_plate.geo on
// z >= 0, x from 0.25 to 0.75 m, z from 0 to 0.25 m, in the plane y = 0 (normal +y, into the
// flow). `mid_span` (z = 0) carries the symmetry support. Structured n x n/2 grid (default
// n = 12, as the full plate's), size_factor 0.5 doubles n.
SetFactory("Built-in");

x_le = 0.25; x_te = 0.75; half_span = 0.25;
n = Round(12 / Mesh.MeshSizeFactor);
m = Round(n / 2);

Point(1) = {x_le, 0, 0};
Point(2) = {x_le, 0, half_span};
Point(3) = {x_te, 0, half_span};
Point(4) = {x_te, 0, 0};
Line(1) = {1, 2};  // leading edge (x = 0.25)
Line(2) = {2, 3};  // side edge z = 0.25
Line(3) = {3, 4};  // trailing edge (x = 0.75)
Line(4) = {4, 1};  // mid-span z = 0 (symmetry)
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = m + 1;
Transfinite Curve{2, 4} = n + 1;
Transfinite Surface{1};

Physical Curve("leading_edge") = {1};
Physical Curve("trailing_edge") = {3};
Physical Curve("side_edge") = {2};
Physical Curve("mid_span") = {4};
Physical Surface("panel") = {1};
