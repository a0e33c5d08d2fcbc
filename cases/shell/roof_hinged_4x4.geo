// Hinged cylindrical roof of Sze, Liu & Lo (2004): R = 2540, length 508 (2 x 254), half-angle
// 0.1 rad, axis along x, crown at y = 0, z = R. Straight edges (phi = +-0.1) hinged, curved
// edges free, point load at the centre. Quarter model x in [0, 254], phi in [0, 0.1]:
// symmetry planes x = 0 ("sym_x") and y = 0 ("sym_y"). 4 x 4 quads split into two
// triangles each; mesh at order 3.
SetFactory("Built-in");
R = 2540; half_length = 254; angle = 0.1; n = 4;
Point(1) = {0, 0, R};  // centre of the roof (load point)
Point(2) = {half_length, 0, R};
Point(3) = {half_length, R * Sin(angle), R * Cos(angle)};
Point(4) = {0, R * Sin(angle), R * Cos(angle)};
Point(5) = {0, 0, 0};
Point(6) = {half_length, 0, 0};
Line(1) = {1, 2};       // crown line (y = 0)
Circle(2) = {2, 6, 3};  // free curved edge (x = 254)
Line(3) = {3, 4};       // hinged straight edge
Circle(4) = {4, 5, 1};  // x = 0
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1};
Physical Curve("sym_y") = {1};
Physical Curve("free") = {2};
Physical Curve("hinged") = {3};
Physical Curve("sym_x") = {4};
Physical Surface("roof") = {1};
