// Scordelis–Lo roof: R = 25, length 50, half-angle 40 deg, axis along x, crown at y = 0,
// z = R. Rigid end diaphragm at x = 0 ("diaphragm"), straight edge at phi = 40 deg free
// ("free"). Quarter model x in [0, 25], phi in [0, 40 deg]: symmetry planes x = 25
// ("sym_x", mid-span) and y = 0 ("sym_y", crown). 8 x 8 quads split into two triangles
// each; mesh at order 3. The reference point is the free edge at mid-span (Point 3).
SetFactory("Built-in");
R = 25; half_length = 25; angle = 40 * Pi / 180; n = 8;
Point(1) = {0, 0, R};
Point(2) = {half_length, 0, R};
Point(3) = {half_length, R * Sin(angle), R * Cos(angle)};
Point(4) = {0, R * Sin(angle), R * Cos(angle)};
Point(5) = {0, 0, 0};
Point(6) = {half_length, 0, 0};
Line(1) = {1, 2};       // crown line (y = 0)
Circle(2) = {2, 6, 3};  // mid-span section (x = 25)
Line(3) = {3, 4};       // free straight edge
Circle(4) = {4, 5, 1};  // end diaphragm (x = 0)
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1};
Physical Curve("sym_y") = {1};
Physical Curve("sym_x") = {2};
Physical Curve("free") = {3};
Physical Curve("diaphragm") = {4};
Physical Surface("roof") = {1};
