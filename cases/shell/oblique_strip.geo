// A plate strip 1 m x 0.1 m on an oblique plane: drawn in z = 0 along x, then rotated by
// 30° about z and by 0.4 rad about x, so that no edge, edge tangent or normal is a
// coordinate axis (checks supports along arbitrary directions). 16 x 1 quads split into
// triangles; mesh it at order 3.
SetFactory("Built-in");
L = 1; b = 0.1; n_along = 16; n_across = 1;
Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, b, 0};
Point(4) = {0, b, 0};
Line(1) = {1, 2};  // long edge y = 0
Line(2) = {2, 3};  // end x = L
Line(3) = {3, 4};  // long edge y = b
Line(4) = {4, 1};  // end x = 0
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n_along + 1;
Transfinite Curve{2, 4} = n_across + 1;
Transfinite Surface{1};
Rotate {{0, 0, 1}, {0, 0, 0}, Pi / 6} { Surface{1}; }
Rotate {{1, 0, 0}, {0, 0, 0}, 0.4} { Surface{1}; }
Physical Curve("ends") = {2, 4};
Physical Curve("sides") = {1, 3};
Physical Surface("strip") = {1};
